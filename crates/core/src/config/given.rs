//! The keys a user gave: every key a configuration file or a `--set` override names, with its
//! value as written and where it was written ([`Place`]). A key that only the defaults hold is not
//! given. The warnings about keys without effect ([`Config::ineffective_keys`]) concern given keys
//! only, and the mistakes of a configuration are reported in the order of their places.

use std::collections::HashMap;

#[cfg(doc)]
use super::Config;

/// Where a key was written. The order is the order of a report: the lines of the file, then the
/// `--set` overrides as given, then what no one wrote.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Place {
    /// This line (1-based) of the configuration file or text.
    Line(usize),
    /// The `--set` override with this index (0-based) in the list given.
    Override(usize),
    /// Nowhere: the key holds its default.
    Default,
}

impl Place {
    /// Where the key was written, as the messages say it: ` at line 3`, ` in --set time.dt=0`
    /// (`overrides` are the overrides the index counts in), or nothing.
    pub fn phrase(self, overrides: &[String]) -> String {
        match self {
            Self::Line(n) => format!(" at line {n}"),
            Self::Override(i) => overrides.get(i).map_or(String::new(), |o| format!(" in --set {o}")),
            Self::Default => String::new(),
        }
    }
}

/// One given key.
#[derive(Clone, Debug, PartialEq)]
pub struct GivenKey {
    /// The key, `section.name`.
    pub key: String,
    /// Its value as written (`2`, `1e10`, `"sine"`).
    pub value: String,
    /// Where it was written (the override when both the file and an override name it).
    pub place: Place,
}

/// The keys a file and its overrides gave, in the order of their places.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GivenKeys {
    keys: Vec<GivenKey>,
    /// The overrides the places count in.
    overrides: Vec<String>,
}

impl GivenKeys {
    /// The keys of `--set`-style `key=value` overrides alone (the FMU's parameters, a restart's
    /// overrides); an override that is no `key=value` is left out.
    pub fn of_overrides(overrides: &[String]) -> Self {
        let mut doc = toml::Table::new();
        for o in overrides {
            let _ = super::overrides::apply_override(&mut doc, o);
        }
        Self::of(&doc, &Lines::default(), overrides)
    }

    /// The leaves of the configuration document `doc` (the file merged with the overrides), placed
    /// by the `lines` of the file and by `overrides`.
    pub(super) fn of(doc: &toml::Table, lines: &Lines, overrides: &[String]) -> Self {
        let mut keys = Vec::new();
        leaves(doc, "", &mut |key, value| {
            let place = place_of(&key, lines, overrides);
            let written = match place {
                Place::Override(i) => overrides[i].split_once('=').map(|(_, v)| v.trim().to_string()),
                Place::Line(_) => lines.values.get(&key).cloned(),
                Place::Default => None,
            };
            keys.push(GivenKey {
                place,
                value: written.unwrap_or_else(|| value.to_string()),
                key,
            })
        });
        keys.sort_by_key(|k| k.place);
        Self {
            keys,
            overrides: overrides.to_vec(),
        }
    }

    /// The given key `key` (`section.name`), if given.
    pub fn get(&self, key: &str) -> Option<&GivenKey> {
        self.keys.iter().find(|k| k.key == key)
    }

    /// Every given key, in the order of their places.
    pub fn iter(&self) -> impl Iterator<Item = &GivenKey> {
        self.keys.iter()
    }

    /// The overrides the places count in.
    pub fn overrides(&self) -> &[String] {
        &self.overrides
    }
}

/// The dotted paths of the leaves of `table` (arrays are leaves): the keys a configuration file
/// sets, in the table's order.
pub fn leaf_keys(table: &toml::Table) -> Vec<String> {
    let mut keys = Vec::new();
    leaves(table, "", &mut |path, _| keys.push(path));
    keys
}

/// Calls `f` with the dotted path and value of every leaf of `table` (arrays are leaves).
fn leaves(table: &toml::Table, prefix: &str, f: &mut dyn FnMut(String, &toml::Value)) {
    for (k, v) in table {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(t) => leaves(t, &path, f),
            other => f(path, other),
        }
    }
}

/// The line of every key of a configuration text, sections and dotted paths included
/// (`time`, `time.dt`), and the text of every value that is no table.
#[derive(Clone, Debug, Default)]
pub(super) struct Lines {
    lines: HashMap<String, usize>,
    values: HashMap<String, String>,
}

impl Lines {
    /// The lines of the keys of `text` (none when it is no TOML: its syntax error is reported
    /// before any key is).
    pub(super) fn of(text: &str) -> Self {
        let mut lines = Self::default();
        if let Ok(doc) = toml::de::DeTable::parse(text) {
            lines.collect(text, doc.get_ref(), "");
        }
        lines
    }

    fn collect(&mut self, text: &str, table: &toml::de::DeTable<'_>, prefix: &str) {
        for (k, v) in table {
            let path = if prefix.is_empty() {
                k.get_ref().to_string()
            } else {
                format!("{prefix}.{}", k.get_ref())
            };
            let start = k.span().start.min(text.len());
            self.lines
                .entry(path.clone())
                .or_insert_with(|| text[..start].matches('\n').count() + 1);
            match v.get_ref() {
                toml::de::DeValue::Table(t) => self.collect(text, t, &path),
                _ => {
                    if let Some(written) = text.get(v.span()) {
                        self.values.insert(path, written.trim().to_string());
                    }
                }
            }
        }
    }
}

/// Where `key` (a dotted path) was written: the last override that names it or a key below it,
/// else its line in the file, else [`Place::Default`].
pub(super) fn place_of(key: &str, lines: &Lines, overrides: &[String]) -> Place {
    let below = format!("{key}.");
    let named = overrides.iter().rposition(|o| {
        let k = o.split_once('=').map_or(o.as_str(), |(k, _)| k).trim();
        k == key || k.starts_with(&below)
    });
    match (named, lines.lines.get(key)) {
        (Some(i), _) => Place::Override(i),
        (None, Some(&line)) => Place::Line(line),
        (None, None) => Place::Default,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_given_key_is_placed_at_its_line_or_at_the_override_that_holds_its_value() {
        let text = "# comment\n[time]\ndt = 5e-3\n\n[torque]\namplitude = 2\nprofile = \"sine\"\n";
        let lines = Lines::of(text);
        let mut doc: toml::Table = text.parse().unwrap();
        let overrides = vec!["torque.amplitude=3".to_string(), "mesh.refine=2".to_string()];
        for o in &overrides {
            super::super::overrides::apply_override(&mut doc, o).unwrap();
        }
        let given = GivenKeys::of(&doc, &lines, &overrides);
        let placed: Vec<(&str, &str, Place)> = given
            .iter()
            .map(|k| (k.key.as_str(), k.value.as_str(), k.place))
            .collect();
        assert_eq!(
            placed,
            [
                ("time.dt", "5e-3", Place::Line(3)),
                ("torque.profile", "\"sine\"", Place::Line(7)),
                ("torque.amplitude", "3", Place::Override(0)),
                ("mesh.refine", "2", Place::Override(1)),
            ]
        );
        assert!(given.get("time.end").is_none(), "a default is not given");
        assert_eq!(Place::Override(1).phrase(&overrides), " in --set mesh.refine=2");
        assert_eq!(place_of("torque", &lines, &overrides), Place::Override(0));
        assert_eq!(place_of("time", &lines, &overrides), Place::Line(2));
    }
}
