//! `pendulum_fem._core`: the Python face of the pendulum's stepper (PyO3, an abi3 extension module
//! built by maturin; the Python package `pendulum_fem` re-exports it).
//!
//! One class, [`PySimulation`] (`pendulum_fem.Simulation`), owns a [`pendulum_fem_core::Simulation`] and
//! the [`pendulum_fem_core::Config`] it was built from:
//!
//! * **Configuration**: a TOML file, a dict (nested, or with dotted keys) and keyword overrides with
//!   the CLI's keys. Dicts and keywords become the CLI's `--set key=value` overrides (each value
//!   written as a TOML literal), so they are merged and checked by [`pendulum_fem_core::Config::load`]
//!   exactly as on the command line.
//! * **Stepping**: `step(dt)`, `step_to(t_end)` and `run(end, dt)` release the GIL; `run` takes
//!   the run driver's steps ([`pendulum_fem_run::driver::PlanSteps`]) and returns the columns of
//!   `results.csv` ([`pendulum_fem_run::rows::header`]: with a wall, the contact columns too;
//!   [`pendulum_fem_run::rows::csv_values`]) as numpy arrays.
//! * **Wall**: `gap`, `contact_force`, `impacts`, `in_contact` and `events` (the rows of the CLI's
//!   `events.csv`) read the stepper's wall ([`pendulum_fem_core::Simulation::gap`]).
//! * **Torque input**: `tau` holds the pivot torque ([`pendulum_fem_core::Simulation::set_torque`]). A
//!   model without a `[torque]` profile has no torque term (so that `Simulation()` is the CLI's
//!   default run bit for bit); setting `tau` before the first step declares one (`torque.profile =
//!   "constant"`, `amplitude = 0`) by rebuilding the simulation from the configuration
//!   ([`pendulum_fem_core::Simulation::build`], as every simulation here is built).
//! * **State**: `snapshot()`/`restore()` as bytes ([`pendulum_fem_core::Snapshot::to_bytes`]) and
//!   pickling (the configuration as TOML and the snapshot).
//! * **Errors**: the Rust message in a Python exception (`errors.rs`): `ValueError` for invalid
//!   input, `UnknownKeyError` (a `KeyError` and a `ValueError`) for a configuration key that names
//!   nothing (the key and the keys allowed where it fails), `ConvergenceError` (a `RuntimeError`)
//!   for a failed step, `OutsideModelError` (a `RuntimeError`) for a step that the model does not
//!   cover (its message names the cause and what to change; a smaller step does not help), the
//!   `OSError` of the cause for files (`FileNotFoundError` for a missing one).

mod errors;
mod overrides;
mod simulation;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use pendulum_fem_run::rows::EVENTS_HEADER;

pub use errors::{ConvergenceError, OutsideModelError};
pub(crate) use overrides::{dict_items, flatten};
pub use simulation::PySimulation;

/// The header of `results.csv`: the column names of `Simulation.run`, with the contact columns of
/// a model with a wall when `wall` is true.
#[pyfunction]
#[pyo3(signature = (wall=false))]
fn csv_columns(wall: bool) -> Vec<String> {
    pendulum_fem_run::rows::header(wall)
        .split(',')
        .map(str::to_string)
        .collect()
}

/// The header of `events.csv`: the keys of the rows of `Simulation.events`.
#[pyfunction]
fn event_columns() -> Vec<&'static str> {
    EVENTS_HEADER.split(',').collect()
}

/// `(n, step)`: a communication step `h` [s] as `n` internal steps of `step <= max_step` [s], by
/// the FMU's rule ([`pendulum_fem_core::simulation::split::internal_steps`]): a multiple of `max_step`
/// (to 1e-9 relative) takes steps of exactly `max_step`, other steps `ceil(h / max_step)` equal
/// ones, reusing `last` (the previous call's internal step) when within 1e-9 of it. A bad value or
/// more than a million internal steps is a `ValueError`.
#[pyfunction]
#[pyo3(signature = (h, max_step, last=None))]
fn internal_steps(h: f64, max_step: f64, last: Option<f64>) -> PyResult<(u64, f64)> {
    pendulum_fem_core::simulation::split::internal_steps(h, max_step, last).map_err(PyValueError::new_err)
}

mod study;

/// The Rust extension module of the `pendulum_fem` package.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PySimulation>()?;
    m.add_function(wrap_pyfunction!(csv_columns, m)?)?;
    m.add_function(wrap_pyfunction!(event_columns, m)?)?;
    m.add_function(wrap_pyfunction!(internal_steps, m)?)?;
    m.add("ConvergenceError", m.py().get_type::<ConvergenceError>())?;
    m.add("OutsideModelError", m.py().get_type::<OutsideModelError>())?;
    m.add("UnknownKeyError", errors::unknown_key_error(m.py())?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    study::register(m)?;
    Ok(())
}
