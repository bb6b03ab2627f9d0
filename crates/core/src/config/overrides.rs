//! The `--set section.key=value` overrides: parsed as TOML values and written into the
//! configuration document at any depth, before it is deserialised.

use crate::error::Error;

/// Applies one `section.key=value` override to a TOML document. The value is read as TOML
/// (numbers, booleans, quoted strings); a bare word that is not valid TOML is taken as a string.
pub(super) fn apply_override(doc: &mut toml::Table, assignment: &str) -> Result<(), Error> {
    let (key, value) = assignment.split_once('=').ok_or_else(|| {
        Error::Config(format!(
            "--set {assignment}: expected key=value, e.g. mesh.max_size=0.01"
        ))
    })?;
    let key = key.trim();
    let value = value.trim();
    let parsed: toml::Value = match format!("v = {value}").parse::<toml::Table>() {
        Ok(mut t) => t.remove("v").expect("parsed key"),
        Err(_) => toml::Value::String(value.to_string()),
    };
    let parts: Vec<&str> = key.split('.').collect();
    if parts.len() < 2 || parts.iter().any(|p| p.is_empty()) {
        return Err(Error::Config(format!(
            "--set {assignment}: the key must be section.name (any depth: a.b.c), e.g. mesh.max_size or time.dt"
        )));
    }
    // walk (and create) the tables of every part but the last, at any depth
    let (last, tables) = parts.split_last().expect("two parts at least");
    let mut table = doc;
    for (depth, part) in tables.iter().enumerate() {
        let entry = table
            .entry(part.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        table = entry.as_table_mut().ok_or_else(|| {
            Error::Config(format!(
                "--set {assignment}: `{}` is a value, not a section",
                parts[..=depth].join(".")
            ))
        })?;
    }
    table.insert(last.to_string(), parsed);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{Config, Plane};

    #[test]
    fn overrides_are_typed_and_checked() {
        let cfg = Config::load(None, &["mesh.max_size=0.01".into(), "material.plane=strain".into()]).unwrap();
        assert_eq!(cfg.mesh.max_size, 0.01);
        assert_eq!(cfg.material.plane, Plane::Strain);
        let err = Config::load(None, &["mesh.max_size=-1".into()])
            .unwrap_err()
            .to_string();
        assert!(err.contains("mesh.max_size"), "{err}");
        // keys of any depth reach nested tables; one that runs through a value says which
        let mut doc = toml::Table::new();
        apply_override(&mut doc, "a.b.c=3").unwrap();
        assert_eq!(doc["a"]["b"]["c"].as_integer(), Some(3));
        let err = apply_override(&mut doc, "a.b.c.d=1").unwrap_err().to_string();
        assert!(err.contains("`a.b.c` is a value"), "{err}");
        let err = Config::load(None, &["time.dt.x=1".into()]).unwrap_err().to_string();
        assert!(err.contains("time.dt"), "{err}");
    }
}
