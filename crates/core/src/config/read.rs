//! Reading a configuration: a TOML file or text, its relative input paths ([`PATH_KEYS`]), the
//! `--set` overrides merged in, deserialised and validated ([`Config::load`], [`Config::from_toml_str`]).

use serde::Deserialize;
use std::path::Path;

use super::overrides::apply_override;
use super::unknown_key::unknown_key_message;
use super::Config;
use crate::error::Error;

impl Config {
    /// Reads a configuration file (or the defaults when `path` is `None`) and applies
    /// `key=value` overrides, then validates.
    pub fn load(path: Option<&Path>, overrides: &[String]) -> Result<Self, Error> {
        let mut text = None;
        let mut doc = match path {
            Some(p) => {
                let read = std::fs::read_to_string(p)
                    .map_err(|e| Error::Config(format!("cannot read config file {}: {e}", p.display())))?;
                let doc = read
                    .parse::<toml::Table>()
                    .map_err(|e| Error::Config(format!("config file {}: {e}", p.display())))?;
                text = Some(read);
                doc
            }
            None => toml::Table::new(),
        };
        if let Some(folder) = path.and_then(Path::parent) {
            resolve_relative_paths(&mut doc, folder);
        }
        for o in overrides {
            apply_override(&mut doc, o)?;
        }
        let source = path.map(|p| p.display().to_string()).unwrap_or_else(|| "--set".into());
        let cfg: Config = Config::deserialize(toml::Value::Table(doc)).map_err(|e| {
            let message = e.to_string();
            let located = unknown_key_message(message.trim(), text.as_deref(), overrides);
            Error::Config(format!(
                "{source}: {}",
                located.unwrap_or_else(|| message.trim().to_string())
            ))
        })?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Parses TOML text (no overrides) and validates.
    pub fn from_toml_str(text: &str) -> Result<Self, Error> {
        let doc = text
            .parse::<toml::Table>()
            .map_err(|e| Error::Config(e.to_string().trim().to_string()))?;
        let cfg: Config = Config::deserialize(toml::Value::Table(doc)).map_err(|e| {
            let message = e.to_string();
            let located = unknown_key_message(message.trim(), Some(text), &[]);
            Error::Config(located.unwrap_or_else(|| message.trim().to_string()))
        })?;
        cfg.validate()?;
        Ok(cfg)
    }
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
