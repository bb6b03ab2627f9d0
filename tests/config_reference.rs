//! The configuration reference, `docs/src/configuration.md`, is generated from the program and
//! checked against it:
//!
//! * the keys, their defaults and their comments are those of the commented file
//!   `pendulum-fem init` writes (`crates/core/src/default_config.toml`); a key the file shows
//!   commented out (`# rod_size = 0.0075`) is one that is unset by default;
//! * every key the program reads is in that file, and the file has no other: serde's own list of a
//!   section's fields, which the error for an unknown key quotes (`(allowed: dt, end, …)`);
//! * a default the file shows is the value of `Config::default()`;
//! * the allowed values are the program's: the messages of `Config::load` for a value outside them
//!   (for a number a large negative, a large positive value and NaN; for a word one that is no
//!   choice), with the other keys at their defaults.
//!
//! The test fails when the page differs from what it generates and says how to regenerate it:
//! `UPDATE_REFERENCE=1 cargo test --release --test suite config_reference::`.

use std::collections::BTreeSet;

use crate::common;
use pendulum_fem::Config;

/// The page, relative to the repository's root.
const PAGE: &str = "docs/src/configuration.md";

/// The command that regenerates [`PAGE`].
const REGENERATE: &str = "UPDATE_REFERENCE=1 cargo test --release --test suite config_reference::";

/// A key of the commented file.
#[derive(Debug)]
struct Entry {
    key: String,
    /// The value as the file writes it (TOML).
    value: String,
    /// `false` for a key the file shows commented out: unset by default.
    set: bool,
    /// Its comment, continuation lines joined.
    comment: String,
}

/// A `[section]` of the commented file.
#[derive(Debug)]
struct Section {
    name: String,
    /// Comment lines of the section that belong to no key.
    notes: Vec<String>,
    entries: Vec<Entry>,
}

/// The text before the first `#` that is outside a quoted string, and the comment after it.
fn split_comment(line: &str) -> (&str, Option<&str>) {
    let mut quoted = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '#' if !quoted => return (line[..i].trim_end(), Some(line[i + 1..].trim())),
            _ => {}
        }
    }
    (line.trim_end(), None)
}

/// `key = value` with a bare key, or `None`.
fn assignment(text: &str) -> Option<(String, String)> {
    let (key, value) = text.split_once('=')?;
    let key = key.trim();
    let bare = !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    (bare && !value.trim().is_empty()).then(|| (key.to_string(), value.trim().to_string()))
}

/// The commented file: its header (the comment lines before the first section) and its sections.
fn parse(text: &str) -> (Vec<String>, Vec<Section>) {
    let (mut header, mut sections) = (Vec::new(), Vec::<Section>::new());
    for (n, line) in text.lines().enumerate() {
        let at = || format!("line {} of `pendulum-fem init`'s file: {line:?}", n + 1);
        let trimmed = line.trim();
        if trimmed.is_empty() {
            continue;
        }
        if let Some(name) = trimmed.strip_prefix('[').and_then(|t| t.strip_suffix(']')) {
            sections.push(Section {
                name: name.to_string(),
                notes: Vec::new(),
                entries: Vec::new(),
            });
            continue;
        }
        let Some(section) = sections.last_mut() else {
            let comment = trimmed.strip_prefix('#').unwrap_or_else(|| panic!("{}", at()));
            header.push(comment.trim().to_string());
            continue;
        };
        if line.starts_with(char::is_whitespace) {
            // a comment continued under the previous key's comment
            let more = trimmed.strip_prefix('#').unwrap_or_else(|| panic!("{}", at()));
            let entry = section.entries.last_mut().unwrap_or_else(|| panic!("{}", at()));
            entry.comment = format!("{} {}", entry.comment, more.trim());
            continue;
        }
        let (set, text) = match trimmed.strip_prefix('#') {
            Some(commented) => (false, commented.trim()),
            None => (true, trimmed),
        };
        let (code, comment) = split_comment(text);
        match assignment(code) {
            Some((key, value)) => section.entries.push(Entry {
                key,
                value,
                set,
                comment: comment.unwrap_or("").to_string(),
            }),
            None if !set => section.notes.push(text.to_string()),
            None => panic!("{}: neither a key nor a comment", at()),
        }
    }
    (header, sections)
}

/// The keys serde allows where `key` is unknown (`key` = `section.name`, or a section alone):
/// the list the program's message quotes, `(allowed: a, b, …)`.
fn allowed_keys(probe: &str) -> BTreeSet<String> {
    let e = Config::load(None, &[format!("{probe}=1")])
        .expect_err("an unknown key is an error")
        .to_string();
    let list = e
        .rsplit_once("(allowed: ")
        .and_then(|(_, rest)| rest.strip_suffix(')'))
        .unwrap_or_else(|| panic!("no list of allowed keys in {e:?}"));
    list.split(", ").map(str::to_string).collect()
}

/// What the program allows for `section.key` whose default (or example) is `value`: the
/// messages for values outside the allowed ones, without the value, or `None` when no probe is
/// refused.
fn allowed_values(section: &str, key: &str, value: &str) -> Option<String> {
    let full = format!("{section}.{key}");
    let is_path = pendulum_fem::config::PATH_KEYS.contains(&(section, key)) || full == "output.dir";
    let parsed = format!("v = {value}")
        .parse::<toml::Table>()
        .unwrap_or_else(|e| panic!("{full} = {value}: {e}"))
        .remove("v")
        .unwrap();
    let probes: &[&str] = match parsed {
        toml::Value::Boolean(_) => return Some("`true` or `false`".into()),
        toml::Value::String(_) if is_path => return Some("a path".into()),
        toml::Value::String(_) => &["\"no-such-choice\"", "-1", "1000000000"],
        toml::Value::Integer(_) => &["0", "1000000000"],
        toml::Value::Float(_) => &["-1e30", "0", "1e30", "nan"],
        other => panic!("{full}: a value of another type, {other:?}"),
    };
    // the wall's dimensions and material are read (and checked) for the deformable block only
    let context: &[&str] = if section == "wall" {
        &["wall.kind=deformable"]
    } else {
        &[]
    };
    let mut said = Vec::<String>::new();
    for probe in probes {
        let mut sets: Vec<String> = context.iter().map(|s| s.to_string()).collect();
        sets.push(format!("{full}={probe}"));
        let Err(e) = Config::load(None, &sets) else {
            continue;
        };
        let e = e.to_string();
        let e = e.lines().next().unwrap_or("").trim();
        // without the place the program adds to a mistake (`(in --set key=value)`): the probe's
        let e = match e.rfind(" (in --set ") {
            Some(at) if e.ends_with(')') => e[..at].trim_end(),
            _ => e,
        };
        let allowed = if let Some((_, choices)) = e
            .split_once("unknown variant")
            .and_then(|(_, m)| m.split_once(", expected "))
        {
            // serde's message for a word that is no choice: `a` or `b`, one of `a`, `b`, `c`
            choices.to_string()
        } else if let Some((at, rule)) = e.split_once(": allowed ") {
            // the range checks: `key = value: allowed RULE`, when they name this key
            if !at.contains(&format!("{full} = ")) {
                continue;
            }
            let rule = rule.strip_prefix("range ").unwrap_or(rule);
            rule.strip_prefix("values are ").unwrap_or(rule).to_string()
        } else {
            continue;
        };
        if !said.contains(&allowed) {
            said.push(allowed);
        }
    }
    (!said.is_empty()).then(|| said.join("; "))
}

/// A table cell: `|` escaped, so that it stays in its cell.
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

/// The page generated from `pendulum-fem init`'s file `text`, after checking it against the keys
/// and defaults of the program; the problems found instead, if any.
fn reference(text: &str) -> Result<String, Vec<String>> {
    let (header, sections) = parse(text);
    let mut problems = Vec::new();

    // the file's keys against those the program reads, and its defaults against the program's
    let names: BTreeSet<String> = sections.iter().map(|s| s.name.clone()).collect();
    let program = allowed_keys("no_such_section.key");
    for missing in program.difference(&names) {
        problems.push(format!("the program reads [{missing}], which the file does not have"));
    }
    for extra in names.difference(&program) {
        problems.push(format!("the file has [{extra}], which the program does not read"));
    }
    let defaults = toml::Table::try_from(Config::default()).expect("the defaults serialise");
    for s in &sections {
        let keys: BTreeSet<String> = s.entries.iter().map(|e| e.key.clone()).collect();
        if !program.contains(&s.name) {
            continue;
        }
        let read = allowed_keys(&format!("{}.no_such_key", s.name));
        for missing in read.difference(&keys) {
            problems.push(format!(
                "the program reads {}.{missing}, which the file does not have",
                s.name
            ));
        }
        for extra in keys.difference(&read) {
            problems.push(format!(
                "the file has {}.{extra}, which the program does not read",
                s.name
            ));
        }
        for e in &s.entries {
            let full = format!("{}.{}", s.name, e.key);
            let default = defaults.get(&s.name).and_then(|t| t.get(&e.key));
            let shown = format!("v = {}", e.value)
                .parse::<toml::Table>()
                .ok()
                .and_then(|mut t| t.remove("v"));
            match (e.set, default) {
                (true, Some(d)) if shown.as_ref() == Some(d) => {}
                (true, d) => problems.push(format!(
                    "{full}: the file shows {}, the program's default is {d:?}",
                    e.value
                )),
                // commented out with its default: it acts only with another key (the program
                // warns when it is set without it)
                (false, Some(d)) if shown.as_ref() == Some(d) => {}
                (false, Some(d)) => problems.push(format!(
                    "{full}: commented out in the file as {}, but the program's default is {d}",
                    e.value
                )),
                (false, None) => {
                    if let Err(err) = Config::load(None, &[format!("{full}={}", e.value)]) {
                        problems.push(format!("{full}: the file's example {} is refused: {err}", e.value));
                    }
                }
            }
        }
    }
    if !problems.is_empty() {
        return Err(problems);
    }

    let mut page = String::new();
    page.push_str("# Configuration\n\n");
    page.push_str(&format!(
        "<!-- Generated by tests/config_reference.rs from `pendulum-fem init` and the program's own \
         checks; do not edit by hand. Regenerate: {REGENERATE} -->\n\n"
    ));
    page.push_str("The file `pendulum-fem init` writes begins:\n\n> ");
    page.push_str(&header.join(" "));
    page.push_str(
        "\n\nA configuration file names only what differs from the defaults; `--set section.key=value` \
         overrides any key of it on the command line (`pendulum-fem run`, `modes`, `mesh`, `sweep`), and \
         the Python package takes the same keys (`Simulation(**{\"initial.angle_deg\": 45})`). \
         `pendulum-fem init FILE` writes the whole file below, commented. A key the program does not \
         read is an error naming the nearest one, and a value outside what it allows an error naming \
         the key, before anything runs.\n\n\
         Each table lists a section's keys in the file's order: the default (*unset*: the key is \
         commented out in the file, with an example value; a default marked \"acts only with another \
         key\" is commented out too, and setting it without that key is warned about), what the program allows (its own message \
         for a value outside, with the other keys at their defaults where the bound depends on them, and \
         `[wall]`'s with `wall.kind = \"deformable\"`, which reads them) and the file's comment (unit \
         and meaning).\n\n",
    );
    page.push_str(
        "```sh\npendulum-fem init my.toml\n\
         pendulum-fem run --config my.toml --set time.end=0.05 --set output.animation=false \\\n    \
         --set output.paraview=false --out from-file\n```\n",
    );
    for s in &sections {
        page.push_str(&format!("\n## `[{}]`\n\n", s.name));
        if !s.notes.is_empty() {
            page.push_str(&format!("{}\n\n", s.notes.join(" ")));
        }
        page.push_str("| key | default | allowed | unit and meaning |\n|---|---|---|---|\n");
        for e in &s.entries {
            let has_default = defaults.get(&s.name).and_then(|t| t.get(&e.key)).is_some();
            let default = match (e.set, has_default) {
                (true, _) => format!("`{}`", e.value),
                (false, true) => format!("`{}` (acts only with another key)", e.value),
                (false, false) => format!("*unset* (e.g. `{}`)", e.value),
            };
            let allowed = allowed_values(&s.name, &e.key, &e.value).unwrap_or_else(|| "any".into());
            page.push_str(&format!(
                "| `{}.{}` | {} | {} | {} |\n",
                s.name,
                e.key,
                cell(&default),
                cell(&allowed),
                cell(&e.comment)
            ));
        }
    }
    Ok(page)
}

#[test]
fn the_configuration_reference_is_generated_from_the_program_and_up_to_date() {
    let root = common::root();
    let dir = common::scratch("init");
    let file = dir.join("init.toml");
    let out = common::bin().arg("init").arg(&file).output().unwrap();
    assert!(out.status.success(), "pendulum-fem init: {out:?}");
    let text = std::fs::read_to_string(&file).unwrap();
    let page = reference(&text).unwrap_or_else(|problems| {
        panic!(
            "`pendulum-fem init`'s file (crates/core/src/default_config.toml) and the program disagree:\n  {}",
            problems.join("\n  ")
        )
    });
    let path = root.join(PAGE);
    if std::env::var_os("UPDATE_REFERENCE").is_some_and(|v| v == "1") {
        std::fs::write(&path, &page).unwrap();
        println!("wrote {PAGE}");
        return;
    }
    let current = std::fs::read_to_string(&path).unwrap_or_default();
    if current != page {
        let first = current
            .lines()
            .zip(page.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(current.lines().count().min(page.lines().count()));
        panic!(
            "{PAGE} is not what the program generates (first difference at line {}):\n  page:      {:?}\n  generated: {:?}\n\
             Regenerate it with\n  {REGENERATE}",
            first + 1,
            current.lines().nth(first).unwrap_or(""),
            page.lines().nth(first).unwrap_or(""),
        );
    }
}

#[test]
fn a_key_missing_from_the_file_or_a_default_that_differs_is_named() {
    let text = pendulum_fem::config::commented_default();
    // a key the program reads, left out of the file
    let without: String = text
        .lines()
        .filter(|l| !l.starts_with("dt = "))
        .map(|l| format!("{l}\n"))
        .collect();
    let problems = reference(&without).unwrap_err();
    assert!(
        problems.iter().any(|p| p.contains("the program reads time.dt")),
        "{problems:?}"
    );
    // a default the file shows wrongly
    let wrong = text.replace("max_iterations = 40", "max_iterations = 41");
    let problems = reference(&wrong).unwrap_err();
    assert!(
        problems
            .iter()
            .any(|p| p.starts_with("solver.max_iterations: the file shows 41")),
        "{problems:?}"
    );
    // a key the program does not read
    let extra = text.replace("[gravity]\n", "[gravity]\nstrength = 1.0\n");
    let problems = reference(&extra).unwrap_err();
    assert!(
        problems
            .iter()
            .any(|p| p.contains("gravity.strength, which the program does not read")),
        "{problems:?}"
    );
}

#[test]
fn the_file_is_read_into_keys_defaults_comments_and_notes() {
    let (header, sections) = parse(
        "# a header\n# on two lines\n\n[mesh]\nmax_size = 0.03  # m, global\n# Local sizes:\n\
         # rod_size = 0.0075  # m, derived\n                     # from the rod\n[output]\ndir = \"a#b\"  # folder\n",
    );
    assert_eq!(header, ["a header", "on two lines"]);
    assert_eq!(sections.len(), 2);
    let mesh = &sections[0];
    assert_eq!(mesh.notes, ["Local sizes:"]);
    assert_eq!(
        (
            mesh.entries[0].key.as_str(),
            mesh.entries[0].value.as_str(),
            mesh.entries[0].set
        ),
        ("max_size", "0.03", true)
    );
    let rod = &mesh.entries[1];
    assert_eq!((rod.key.as_str(), rod.set), ("rod_size", false));
    assert_eq!(rod.comment, "m, derived from the rod");
    assert_eq!(
        sections[1].entries[0].value, "\"a#b\"",
        "a # inside quotes is no comment"
    );
}
