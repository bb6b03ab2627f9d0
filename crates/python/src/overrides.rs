//! Configuration from Python: a dict of configuration keys (nested or dotted) and keyword values
//! as TOML values and the CLI's `key=value` overrides, loaded as the CLI loads them (an unknown key
//! named; the keys given kept for the warnings about keys without effect), and a configuration
//! written back as portable TOML.

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use pendulum_fem_core::config::Loaded;
use pendulum_fem_core::{Config, Error};

use crate::errors::{os_error, py_err, unknown_key};

/// A Python value as a TOML value (`None`: no value, the key keeps its default).
fn toml_value(key: &str, v: &Bound<'_, PyAny>) -> PyResult<Option<toml::Value>> {
    if v.is_none() {
        return Ok(None);
    }
    let value = if v.is_instance_of::<PyBool>() {
        toml::Value::Boolean(v.extract()?)
    } else if v.is_instance_of::<PyInt>() {
        toml::Value::Integer(v.extract()?)
    } else if v.is_instance_of::<PyFloat>() {
        toml::Value::Float(v.extract()?)
    } else if v.is_instance_of::<PyString>() {
        toml::Value::String(v.extract()?)
    } else if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for item in v.try_iter()? {
            if let Some(x) = toml_value(key, &item?)? {
                items.push(x);
            }
        }
        toml::Value::Array(items)
    } else if v.hasattr("__fspath__")? {
        let os = v.py().import("os")?;
        toml::Value::String(os.call_method1("fspath", (v,))?.extract()?)
    } else if let Ok(i) = v.extract::<i64>() {
        // numpy integers and other objects with __index__
        toml::Value::Integer(i)
    } else if let Ok(x) = v.extract::<f64>() {
        toml::Value::Float(x)
    } else {
        return Err(PyValueError::new_err(format!(
            "configuration key `{key}`: a {} is not a configuration value (numbers, booleans, strings, paths)",
            v.get_type().name()?
        )));
    };
    Ok(Some(value))
}

/// The `(dotted key, value)` pairs of a dict of configuration keys: nested dicts join their keys
/// with dots, `None` leaves a key out. The one reading of a configuration dict, for the overrides
/// of a simulation ([`flatten`]) and a study's cases; `what` starts an error message.
pub(crate) fn dict_items(prefix: &str, dict: &Bound<'_, PyDict>, what: &str) -> PyResult<Vec<(String, toml::Value)>> {
    let mut out = Vec::new();
    for (k, v) in dict.iter() {
        let k: String = k
            .extract()
            .map_err(|_| PyValueError::new_err(format!("{what}configuration keys are strings, got {k:?}")))?;
        let key = if prefix.is_empty() { k } else { format!("{prefix}.{k}") };
        if let Ok(sub) = v.cast::<PyDict>() {
            out.extend(dict_items(&key, sub, what)?);
        } else if let Some(value) = toml_value(&key, &v)? {
            out.push((key, value));
        }
    }
    Ok(out)
}

/// Appends the `key=value` overrides of a dict ([`dict_items`]).
pub(crate) fn flatten(dict: &Bound<'_, PyDict>, out: &mut Vec<String>) -> PyResult<()> {
    out.extend(
        dict_items("", dict, "")?
            .into_iter()
            .map(|(key, value)| format!("{key}={value}")),
    );
    Ok(())
}

/// The first key of `keys` (dotted) that names nothing in the configuration, with the section
/// where it fails and the keys allowed there: walked through the default configuration as JSON
/// (`None` fields are `null`, so every key is there; below a value that is no section nothing is
/// checked). Only used to name the key of an error the library already reported.
fn first_unknown_key(keys: impl IntoIterator<Item = String>) -> Option<(String, String, Vec<String>)> {
    let defaults = serde_json::to_value(Config::default()).unwrap_or(serde_json::Value::Null);
    keys.into_iter().find_map(|key| {
        let mut node = &defaults;
        let mut section: Vec<&str> = Vec::new();
        for part in key.split('.') {
            let fields = node.as_object()?;
            match fields.get(part) {
                Some(next) => {
                    node = next;
                    section.push(part);
                }
                None => {
                    let allowed = fields.keys().cloned().collect();
                    return Some((key.clone(), section.join("."), allowed));
                }
            }
        }
        None
    })
}

/// Loads a configuration as the CLI does (`--config FILE --set …`), with the keys the file and the
/// overrides gave. A file that cannot be opened is the `OSError` of its cause
/// (`FileNotFoundError`); an unknown key, in the file or the overrides, an `UnknownKeyError`
/// naming it and the keys allowed where it fails.
pub(crate) fn load_config(path: Option<std::path::PathBuf>, overrides: &[String]) -> PyResult<Loaded> {
    if let Some(p) = &path {
        std::fs::File::open(p).map_err(|e| os_error(p, &e))?;
    }
    Config::load_given(path.as_deref(), overrides).map_err(|e| {
        let Error::Config(message) = &e else {
            return py_err(e);
        };
        if !pendulum_fem_core::config::reports_an_unknown_key(message) {
            return py_err(e);
        }
        let mut keys = path
            .as_ref()
            .and_then(|p| std::fs::read_to_string(p).ok())
            .and_then(|text| text.parse::<toml::Table>().ok())
            .map_or_else(Vec::new, |table| pendulum_fem_core::config::leaf_keys(&table));
        keys.extend(
            overrides
                .iter()
                .map(|o| o.split_once('=').map_or(o.as_str(), |(k, _)| k).trim().to_string()),
        );
        match first_unknown_key(keys) {
            Some((key, section, allowed)) => unknown_key(&key, &section, &allowed),
            None => py_err(e),
        }
    })
}

/// The configuration as TOML that reads back to the same value (file paths made absolute).
pub(crate) fn config_toml(cfg: &Config) -> PyResult<String> {
    pendulum_fem_run::files::portable_toml(cfg, "configuration as TOML")
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))
}
