//! The module's exceptions and the one mapping of a Rust error to a Python exception, in Python's
//! words: invalid input a `ValueError`, an unknown configuration key `UnknownKeyError` (a `KeyError`
//! and a `ValueError`), a failed step (a state with a NaN or an infinity too) `ConvergenceError`, a
//! step outside the model `OutsideModelError`, files the `OSError` subclass of their cause
//! (`FileNotFoundError` for a missing file). A message is the library's without the command line's
//! framing (its `configuration:` category, `--set`), which the exception's type and the call say.

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyType};

use pendulum_fem_core::Error;

pyo3::create_exception!(
    pendulum_fem,
    ConvergenceError,
    pyo3::exceptions::PyRuntimeError,
    "A time step (or the initial equilibrium) failed after every cut-back, or reached a state with a \
     NaN or an infinity; the simulation is left exactly as before the call."
);

pyo3::create_exception!(
    pendulum_fem,
    OutsideModelError,
    pyo3::exceptions::PyRuntimeError,
    "A time step leads outside what the model covers (the message names the cause and what to \
     change); the simulation is left exactly as before the call."
);

/// `UnknownKeyError`: both a `KeyError` (what Python raises for a name not in a mapping) and a
/// `ValueError` (what every other bad configuration raises), so either `except` catches it. Its
/// text is the message as given (a `KeyError` alone would show it quoted).
const UNKNOWN_KEY_ERROR: &std::ffi::CStr = cr#"
class UnknownKeyError(KeyError, ValueError):
    """A configuration key that names nothing: ``key`` is the dotted key, ``allowed`` the keys
    allowed where it fails (the section's, or the sections at the top level)."""

    __module__ = "pendulum_fem"

    def __init__(self, message, key=None, allowed=()):
        super().__init__(message)
        self.key = key
        self.allowed = list(allowed)

    def __str__(self):
        return str(self.args[0]) if self.args else ""
"#;

/// The class `pendulum_fem.UnknownKeyError`, made once.
pub(crate) fn unknown_key_error(py: Python<'_>) -> PyResult<&Bound<'_, PyType>> {
    static TYPE: PyOnceLock<Py<PyType>> = PyOnceLock::new();
    let t = TYPE.get_or_try_init(py, || -> PyResult<Py<PyType>> {
        let globals = PyDict::new(py);
        py.run(UNKNOWN_KEY_ERROR, Some(&globals), None)?;
        let class = globals
            .get_item("UnknownKeyError")?
            .expect("the code above defines the class");
        Ok(class.cast_into::<PyType>()?.unbind())
    })?;
    Ok(t.bind(py))
}

/// An `UnknownKeyError` for the dotted `key`, `allowed` the keys allowed where it fails.
pub(crate) fn unknown_key(key: &str, section: &str, allowed: &[String]) -> PyErr {
    Python::attach(|py| {
        let within = if section.is_empty() {
            "at the top level".to_string()
        } else {
            format!("in [{section}]")
        };
        let message = format!(
            "unknown configuration key '{key}' (allowed {within}: {})",
            allowed.join(", ")
        );
        match unknown_key_error(py).and_then(|t| t.call1((message, key, allowed.to_vec()))) {
            Ok(e) => PyErr::from_value(e),
            Err(e) => e,
        }
    })
}

/// A message of the library without the command line's framing: its `--set`, as a prefix or as
/// the place of a mistake: Python's overrides are keywords and dicts.
fn in_python_words(message: String) -> String {
    let mut message = match message
        .strip_prefix("--set: ")
        .or_else(|| message.strip_prefix("--set "))
    {
        Some(rest) => rest.to_string(),
        None => message,
    };
    // `… (in --set key=value)` after a mistake, `key in --set key=value: …` before one
    for (place, end, keep) in [(" (in --set ", ")", 0), (" in --set ", ": ", 2)] {
        while let Some(start) = message.find(place) {
            let Some(len) = message[start..].find(end) else { break };
            message.replace_range(start..start + len + end.len() - keep, "");
        }
    }
    message
}

/// An `OSError` with the cause's `errno`, its text and the file, which Python makes the subclass
/// of the cause (`FileNotFoundError`, `PermissionError`, `IsADirectoryError`, …).
pub(crate) fn os_error(path: &std::path::Path, source: &std::io::Error) -> PyErr {
    match source.raw_os_error() {
        Some(code) => {
            let text = std::io::Error::from_raw_os_error(code).to_string();
            // the text without Rust's " (os error N)": Python shows `[Errno N]` itself
            let text = text.split(" (os error").next().unwrap_or(&text).to_string();
            PyOSError::new_err((code, text, path.display().to_string()))
        }
        None => PyOSError::new_err(format!("{}: {source}", path.display())),
    }
}

/// The Rust error as a Python exception (see the module documentation).
pub(crate) fn py_err(e: Error) -> PyErr {
    match e {
        Error::TimeStep { .. } | Error::InitialEquilibrium { .. } | Error::NonFinite { .. } => {
            ConvergenceError::new_err(e.to_string())
        }
        Error::OutsideModel { .. } => OutsideModelError::new_err(e.to_string()),
        Error::Io { path, source } => os_error(&path, &source),
        Error::Config(m) | Error::Input(m) => PyValueError::new_err(in_python_words(m)),
        Error::Geometry(_) | Error::Mesh(_) | Error::InvertedElement { .. } => PyValueError::new_err(e.to_string()),
        _ => PyRuntimeError::new_err(e.to_string()),
    }
}
