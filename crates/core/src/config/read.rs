//! Reading a configuration: a TOML file or text, its relative input paths ([`PATH_KEYS`]), the
//! `--set` overrides merged in, deserialised key by key and validated ([`Config::load_given`],
//! [`Config::load`], [`Config::from_toml_str`]).
//!
//! Every mistake is found before any is reported: an override that is no `key=value`, an unknown
//! key, a value of the wrong type (each key is deserialised on its own, and a key that fails is
//! left at its default for the rest) and every value out of range ([`Config::validate`] on what
//! remains). The error lists them in the order they were written ([`super::ranges::report`]). A
//! TOML syntax error stops the reading at once: there is no document to look further into.

use serde::Deserialize;
use std::path::Path;

use super::given::{place_of, GivenKeys, Lines, Place};
use super::ineffective::{Ineffective, Use};
use super::overrides::apply_override;
use super::ranges::{report, Mistake};
use super::unknown_key::unknown_key_message;
use super::Config;
use crate::error::Error;

/// A configuration as read, with the keys its file and overrides gave.
#[derive(Clone, Debug, PartialEq)]
pub struct Loaded {
    /// The configuration, validated.
    pub config: Config,
    /// The keys the file and the overrides named.
    pub given: GivenKeys,
}

impl Loaded {
    /// The given keys that have no effect in this configuration under `used`
    /// ([`Config::ineffective_keys`]).
    pub fn ineffective(&self, used: Use) -> Vec<Ineffective> {
        self.config.ineffective_keys(&self.given, used)
    }
}

impl Config {
    /// Reads a configuration file (or the defaults when `path` is `None`) and applies
    /// `key=value` overrides, then validates.
    pub fn load(path: Option<&Path>, overrides: &[String]) -> Result<Self, Error> {
        Self::load_given(path, overrides).map(|loaded| loaded.config)
    }

    /// [`Config::load`], with the keys the file and the overrides gave (for the warnings about
    /// keys without effect, [`Loaded::ineffective`]).
    pub fn load_given(path: Option<&Path>, overrides: &[String]) -> Result<Loaded, Error> {
        let text = path
            .map(|p| {
                std::fs::read_to_string(p)
                    .map_err(|e| Error::Config(format!("cannot read config file {}: {e}", p.display())))
            })
            .transpose()?;
        let name = path.map(|p| p.display().to_string());
        let doc = match (&text, path) {
            (Some(t), Some(p)) => t
                .parse::<toml::Table>()
                .map_err(|e| Error::Config(format!("config file {}: {e}", p.display())))?,
            _ => toml::Table::new(),
        };
        read(
            doc,
            text.as_deref(),
            name.as_deref(),
            path.and_then(Path::parent),
            overrides,
        )
    }

    /// Parses TOML text (no overrides) and validates.
    pub fn from_toml_str(text: &str) -> Result<Self, Error> {
        let doc = text
            .parse::<toml::Table>()
            .map_err(|e| Error::Config(e.to_string().trim().to_string()))?;
        read(doc, Some(text), None, None, &[]).map(|loaded| loaded.config)
    }
}

/// The configuration of the document `doc` (of the configuration text `text`, named `name`, in
/// `folder`) with `overrides` merged in, or the error listing every mistake.
fn read(
    mut doc: toml::Table,
    text: Option<&str>,
    name: Option<&str>,
    folder: Option<&Path>,
    overrides: &[String],
) -> Result<Loaded, Error> {
    let lines = text.map(Lines::of).unwrap_or_default();
    if let Some(folder) = folder {
        resolve_relative_paths(&mut doc, folder);
    }
    let mut mistakes = Vec::new();
    for (i, o) in overrides.iter().enumerate() {
        if let Err(e) = apply_override(&mut doc, o) {
            let message = match e {
                Error::Config(m) => m,
                other => other.to_string(),
            };
            mistakes.push(Mistake::at("", message, Place::Override(i)));
        }
    }
    let given = GivenKeys::of(&doc, &lines, overrides);
    let config = deserialize_each(doc, &lines, overrides, &mut mistakes);
    mistakes.extend(config.mistakes());
    report(mistakes, &given, name)?;
    Ok(Loaded { config, given })
}

/// Deserialises `doc` key by key: a key that is unknown or whose value does not fit is a mistake
/// (at its place, by `lines` and `overrides`) and is left out, so that the configuration of the
/// other keys is found and checked too.
fn deserialize_each(doc: toml::Table, lines: &Lines, overrides: &[String], mistakes: &mut Vec<Mistake>) -> Config {
    let one = |section: &str, value: toml::Value| {
        let mut t = toml::Table::new();
        t.insert(section.to_string(), value);
        Config::deserialize(toml::Value::Table(t)).err()
    };
    let mut fail = |key: String, e: toml::de::Error| {
        let place = place_of(&key, lines, overrides);
        let phrase = place.phrase(overrides);
        let message = e.to_string();
        let message = message.trim();
        let text = unknown_key_message(message, &phrase).unwrap_or_else(|| {
            // serde's own words, without the `in` line that names the key we name
            let what = message.split_once("\nin `").map_or(message, |(what, _)| what);
            format!("{key}{phrase}: {what}")
        });
        mistakes.push(Mistake::at(key, text, place));
    };
    let mut kept = toml::Table::new();
    for (section, value) in doc {
        let toml::Value::Table(keys) = value else {
            match one(&section, value.clone()) {
                Some(e) => fail(section, e),
                None => {
                    kept.insert(section, value);
                }
            }
            continue;
        };
        if let Some(e) = one(&section, toml::Value::Table(toml::Table::new())) {
            fail(section, e);
            continue;
        }
        let mut section_kept = toml::Table::new();
        for (key, value) in keys {
            let mut single = toml::Table::new();
            single.insert(key.clone(), value.clone());
            match one(&section, toml::Value::Table(single)) {
                Some(e) => fail(format!("{section}.{key}"), e),
                None => {
                    section_kept.insert(key, value);
                }
            }
        }
        kept.insert(section, toml::Value::Table(section_kept));
    }
    // each key deserialised on its own: together they do too
    Config::deserialize(toml::Value::Table(kept)).unwrap_or_else(|e| {
        mistakes.push(Mistake::at("", e.to_string().trim().to_string(), Place::Default));
        Config::default()
    })
}

/// Keys naming input files; in a configuration file, a relative one is relative to the file's
/// folder. (`output.dir` is not an input: like `--out`, it is relative to where the run starts.)
pub const PATH_KEYS: [(&str, &str); 2] = [("torque", "file"), ("mesh", "file")];

/// Makes the relative paths of [`PATH_KEYS`] in a configuration file's document relative to the
/// file's folder (`folder`); absolute paths and values that are not strings are left alone (the
/// latter fail with their key when deserialised).
fn resolve_relative_paths(doc: &mut toml::Table, folder: &Path) {
    for (section, key) in PATH_KEYS {
        let value = doc
            .get_mut(section)
            .and_then(toml::Value::as_table_mut)
            .and_then(|t| t.get_mut(key));
        if let Some(toml::Value::String(p)) = value {
            if Path::new(p.as_str()).is_relative() {
                *p = folder.join(p.as_str()).to_string_lossy().into_owned();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mistake_is_reported_once_in_the_order_written() {
        // the later section first in the document's own order (mesh < time): the report is by line
        let text = "[time]\ndt = 0.02\nedn = 2.0\n\n[mesh]\nmax_size = -1\norder = \"two\"\n[tme]\n";
        let overrides = ["gravity.g=-1".to_string(), "nope=1".to_string()];
        let dir = std::env::temp_dir().join(format!("pendulum-fem-mistakes-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("two.toml");
        std::fs::write(&file, text).unwrap();
        let e = Config::load(Some(&file), &overrides).unwrap_err().to_string();
        let order = [
            "6 mistakes, in the order written",
            "unknown key \"edn\" in [time] at line 3; did you mean \"end\"?",
            "mesh.max_size = -1: allowed a finite value > 0 m (at line 6)",
            "mesh.order at line 7: invalid type: string \"two\", expected u32",
            "unknown key \"tme\" at the top level at line 8; did you mean \"time\"?",
            "gravity.g = -1: allowed a finite value >= 0 m/s^2 (in --set gravity.g=-1)",
            "--set nope=1: the key must be section.name",
        ];
        let at: Vec<usize> = order
            .iter()
            .map(|o| e.find(o).unwrap_or_else(|| panic!("{o:?} missing in\n{e}")))
            .collect();
        assert!(at.windows(2).all(|w| w[0] < w[1]), "out of order:\n{e}");
        assert!(e.starts_with("configuration: "), "{e}");
        assert!(e.contains("two.toml: 6 mistakes"), "{e}");
        // the same text without a file: by line too
        let e = Config::from_toml_str(text).unwrap_err().to_string();
        assert!(e.contains("4 mistakes") && e.find("edn") < e.find("tme"), "{e}");
        // one mistake reads as before
        let e = Config::load(None, &["time.dt=0".into()]).unwrap_err().to_string();
        assert_eq!(
            e,
            "configuration: time.dt = 0: allowed a finite value > 0 s (in --set time.dt=0)"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn relative_paths_in_a_file_are_relative_to_its_folder_and_overrides_to_the_current_one() {
        let dir = std::env::temp_dir().join(format!("pendulum-fem-config-paths-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("p.toml");
        std::fs::write(
            &file,
            "[torque]\nprofile = \"table\"\nfile = \"t.csv\"\n[mesh]\nfile = \"m.msh\"\n[output]\ndir = \"out\"\n",
        )
        .unwrap();
        let cfg = Config::load(Some(&file), &[]).unwrap();
        assert_eq!(cfg.torque.file.as_deref(), Some(dir.join("t.csv").as_path()));
        assert_eq!(cfg.mesh.file.as_deref(), Some(dir.join("m.msh").as_path()));
        assert_eq!(
            cfg.output.dir,
            Path::new("out"),
            "an output folder is relative to the current folder"
        );
        let cfg = Config::load(Some(&file), &["torque.file=u.csv".into()]).unwrap();
        assert_eq!(cfg.torque.file.as_deref(), Some(Path::new("u.csv")), "--set: as typed");
        let absolute = dir.join("abs.csv");
        std::fs::write(&file, format!("[torque]\nprofile = \"table\"\nfile = {:?}\n", absolute)).unwrap();
        let cfg = Config::load(Some(&file), &[]).unwrap();
        assert_eq!(cfg.torque.file.as_deref(), Some(absolute.as_path()));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
