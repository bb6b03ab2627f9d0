//! The module's exceptions and the one mapping of a Rust error to a Python exception: invalid input
//! a `ValueError`, a failed step (a state with a NaN or an infinity too) `ConvergenceError`, a step
//! outside the model `OutsideModelError`, files `OSError`.

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

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

/// The Rust error as a Python exception with the Rust message.
pub(crate) fn py_err(e: Error) -> PyErr {
    let message = e.to_string();
    match e {
        Error::TimeStep { .. } | Error::InitialEquilibrium { .. } | Error::NonFinite { .. } => {
            ConvergenceError::new_err(message)
        }
        Error::OutsideModel { .. } => OutsideModelError::new_err(message),
        Error::Io { .. } => PyOSError::new_err(message),
        Error::Config(_) | Error::Input(_) | Error::Geometry(_) | Error::Mesh(_) | Error::InvertedElement { .. } => {
            PyValueError::new_err(message)
        }
        _ => PyRuntimeError::new_err(message),
    }
}
