//! The message for an unknown key: its section, where it was written (the line of the file or
//! the `--set` override) and the allowed key nearest to it by edit distance.

#[cfg(doc)]
use super::Config;
#[cfg(doc)]
use crate::error::Error;

/// For serde's "unknown field" error (`message`: ``unknown field `edn`, expected one of `dt`,
/// `end`, …`` and, in a section, ``in `time` ``), a message that names the key, its section, where
/// it was written (`place`: ` at line 3`, ` in --set time.edn=2` or nothing) and the allowed key
/// nearest to it:
/// `unknown key "edn" in [time] at line 3; did you mean "end"? (allowed: dt, end, …)`.
/// `None` for any other error.
pub(super) fn unknown_key_message(message: &str, place: &str) -> Option<String> {
    let rest = message.strip_prefix("unknown field `")?;
    let (key, rest) = rest.split_once('`')?;
    let (expected, section) = match rest.rsplit_once("\nin `") {
        Some((expected, section)) => (expected, Some(section.trim_end_matches('`'))),
        None => (rest, None),
    };
    // the allowed keys: every `quoted` word after "expected" (`a`; `a` or `b`; one of `a`, `b`, …)
    let allowed: Vec<&str> = expected.split('`').skip(1).step_by(2).collect();
    let within = section.map_or(" at the top level".to_string(), |s| format!(" in [{s}]"));
    let nearest = allowed
        .iter()
        .map(|a| (edit_distance(key, a), *a))
        .min()
        .filter(|(d, a)| *d <= 2.max(a.chars().count() / 3))
        .map_or(String::new(), |(_, a)| format!("; did you mean \"{a}\"?"));
    Some(format!(
        "unknown key \"{key}\"{within}{place}{nearest} (allowed: {})",
        allowed.join(", ")
    ))
}

/// Whether `message` (the text of an [`Error::Config`]) reports an unknown key, as
/// [`Config::load`] words it; for callers that treat a misspelled key apart from a bad value.
pub fn reports_an_unknown_key(message: &str) -> bool {
    message.contains("unknown key \"")
}

/// The optimal-string-alignment distance of `a` and `b`: insertions, deletions, substitutions and
/// swaps of two neighbours (`edn` → `end`: 1) each count 1.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for i in 0..=a.len() {
        d[i][0] = i;
    }
    for j in 0..=b.len() {
        d[0][j] = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            d[i][j] = (d[i - 1][j] + 1).min(d[i][j - 1] + 1).min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d[i][j] = d[i][j].min(d[i - 2][j - 2] + 1);
            }
        }
    }
    d[a.len()][b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;

    #[test]
    fn a_misspelled_key_names_its_section_line_and_nearest_allowed_key() {
        let dir = std::env::temp_dir().join(format!("pendulum-config-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("bad.toml");
        for (text, says) in [
            (
                "[time]\ndt = 0.01\nedn = 2.0\n",
                "unknown key \"edn\" in [time] at line 3; did you mean \"end\"? (allowed: dt, end,",
            ),
            (
                "# a comment\n\n[tme]\ndt = 0.01\n",
                "unknown key \"tme\" at the top level at line 3; did you mean \"time\"?",
            ),
            (
                "[mesh]\nmax_sise = 0.01\n",
                "unknown key \"max_sise\" in [mesh] at line 2; did you mean \"max_size\"?",
            ),
            (
                "[wall]\nkind = \"rigid\"\n[contact]\nstifness = 1e10\n",
                "unknown key \"stifness\" in [contact] at line 4; did you mean \"stiffness\"?",
            ),
        ] {
            std::fs::write(&file, text).unwrap();
            let e = Config::load(Some(&file), &[]).unwrap_err().to_string();
            assert!(e.contains(says), "{text:?}:\n{e}\nshould contain\n{says}");
            let e = Config::from_toml_str(text).unwrap_err().to_string();
            assert!(e.contains(says), "from_toml_str({text:?}):\n{e}");
        }
        // nothing near: no guess, but the allowed keys
        std::fs::write(&file, "[time]\nwhatever = 1\n").unwrap();
        let e = Config::load(Some(&file), &[]).unwrap_err().to_string();
        assert!(
            e.contains("unknown key \"whatever\" in [time] at line 2 (allowed: dt, end"),
            "{e}"
        );
        assert!(!e.contains("did you mean"), "{e}");
        // from --set: the override is named instead of a line
        std::fs::write(&file, "[time]\ndt = 0.01\n").unwrap();
        let e = Config::load(Some(&file), &["time.edn=2".into()])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("unknown key \"edn\" in [time] in --set time.edn=2; did you mean \"end\"?"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn edit_distance_counts_a_swap_of_neighbours_as_one() {
        for (a, b, d) in [
            ("edn", "end", 1),
            ("end", "end", 0),
            ("max_sise", "max_size", 1),
            ("tme", "time", 1),
            ("", "dt", 2),
            ("kitten", "sitting", 3),
        ] {
            assert_eq!(edit_distance(a, b), d, "{a} → {b}");
        }
    }
}
