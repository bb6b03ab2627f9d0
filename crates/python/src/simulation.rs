//! The `Simulation` class ([`PySimulation`]): a stepper and the configuration it was built from,
//! with stepping, the wall and torque input, the state as bytes and pickling, and the fields and
//! properties of the current state as numpy arrays and numbers.

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList, PyString};

use pendulum_fem_core::config::Use;
use pendulum_fem_core::{Config, Simulation, Snapshot};
use pendulum_fem_run::driver::PlanSteps;
use pendulum_fem_run::rows::{csv_values, EVENTS_HEADER};

use crate::errors::py_err;
use crate::overrides::{config_toml, flatten, load_config};

/// How often `run` looks for Ctrl-C (in the main thread).
const SIGNAL_CHECK: std::time::Duration = std::time::Duration::from_millis(50);

/// Meshes and sets up a simulation of `cfg` (without the GIL, [`Simulation::build`]); a mesh-size
/// warning becomes a Python `UserWarning`.
fn build(py: Python<'_>, cfg: &Config) -> PyResult<Simulation> {
    let built = py.detach(|| Simulation::build(cfg)).map_err(py_err)?;
    if let Some(w) = built.mesh_warning {
        user_warning(py, w)?;
    }
    Ok(built.simulation)
}

/// Raises `text` as a Python `UserWarning`.
fn user_warning(py: Python<'_>, text: String) -> PyResult<()> {
    PyErr::warn(py, &py.get_type::<PyUserWarning>(), &std::ffi::CString::new(text)?, 1)
}

/// What `__reduce__` returns: the function that rebuilds a simulation and its arguments (the
/// configuration as TOML, the snapshot).
type Reduced<'py> = (Bound<'py, PyAny>, (String, Bound<'py, PyBytes>));

/// A deformable pendulum simulation (finite elements, hyperelastic, on a hinge under gravity).
///
/// `Simulation(config=None, **overrides)`: `config` is a TOML file (path), a dict of the CLI's
/// configuration keys (nested sections or dotted keys) or `None` for the defaults; keyword
/// overrides use the same keys (`Simulation(time={"dt": 0.005})`, `Simulation(**{"time.dt":
/// 0.005})`) and win over `config`. A value of `None` leaves a key as it is. A key given that has
/// no effect here (`torque.amplitude` without a torque profile, `[output]`, which a Simulation
/// does not write) raises a `UserWarning` naming it and what would make it act.
#[pyclass(module = "pendulum_fem", name = "Simulation")]
pub struct PySimulation {
    sim: Simulation,
    config: Config,
}

impl PySimulation {
    fn from_config(py: Python<'_>, config: Config) -> PyResult<Self> {
        let sim = build(py, &config)?;
        let mut s = Self { sim, config };
        s.warn(py)?;
        Ok(s)
    }

    /// The simulation's warning since the last look (the reduced body's, once, when it does not
    /// apply) as a Python `UserWarning`.
    fn warn(&mut self, py: Python<'_>) -> PyResult<()> {
        match self.sim.take_warning() {
            Some(w) => user_warning(py, w),
            None => Ok(()),
        }
    }

    /// Rebuilds the model with a torque input (before the first step only).
    fn declare_torque_input(&mut self, py: Python<'_>) -> PyResult<()> {
        if self.sim.step > 0 {
            return Err(PyValueError::new_err(
                "tau: this model has no torque input (torque.profile = \"none\") and has already stepped; \
                 set tau before the first step, or declare the input up front with \
                 Simulation(torque={\"profile\": \"constant\"})",
            ));
        }
        let config = self.config.with_torque_input();
        // the pendulum's mesh again (the model's mesh holds every body: a deformable wall's block
        // would be appended twice)
        self.sim = py.detach(|| Simulation::build(&config)).map_err(py_err)?.simulation;
        self.config = config;
        Ok(())
    }

    fn pairs<'py>(py: Python<'py>, flat: &[f64]) -> PyResult<Bound<'py, PyArray2<f64>>> {
        PyArray1::from_slice(py, flat).reshape([flat.len() / 2, 2])
    }
}

#[pymethods]
impl PySimulation {
    #[new]
    #[pyo3(signature = (config=None, **overrides))]
    fn new(py: Python<'_>, config: Option<&Bound<'_, PyAny>>, overrides: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let mut path = None;
        let mut sets = Vec::new();
        if let Some(c) = config.filter(|c| !c.is_none()) {
            if let Ok(dict) = c.cast::<PyDict>() {
                flatten(dict, &mut sets)?;
            } else if c.is_instance_of::<PyString>() || c.hasattr("__fspath__")? {
                let os = py.import("os")?;
                let p: std::path::PathBuf = os.call_method1("fspath", (c,))?.extract()?;
                path = Some(p);
            } else {
                return Err(PyValueError::new_err(format!(
                    "config: a TOML file path, a dict or None, got a {}",
                    c.get_type().name()?
                )));
            }
        }
        if let Some(kw) = overrides {
            flatten(kw, &mut sets)?;
        }
        let loaded = load_config(path, &sets)?;
        // a stepped simulation: the keys a Simulation does not use, as the CLI words them
        for w in loaded.ineffective(Use::Stepper) {
            user_warning(py, w.to_string())?;
        }
        Self::from_config(py, loaded.config)
    }

    /// Rebuilds a pickled simulation: its configuration (TOML) and its snapshot.
    #[staticmethod]
    fn _from_state(py: Python<'_>, config_toml: &str, snapshot: &[u8]) -> PyResult<Self> {
        let cfg = Config::from_toml_str(config_toml).map_err(py_err)?;
        let mut s = Self::from_config(py, cfg)?;
        s.restore(snapshot)?;
        Ok(s)
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Reduced<'py>> {
        let rebuild = py.import("pendulum_fem")?.getattr("_rebuild_simulation")?;
        Ok((rebuild, (config_toml(&self.config)?, self.snapshot(py))))
    }

    /// Advances by `dt` [s] (any finite `dt > 0`; the GIL is released) and returns the Newton
    /// iterations of the step. `n` calls with the same `dt` land on `t0 + n·dt` exactly. A step that
    /// fails raises `ConvergenceError` and leaves the state exactly as before.
    fn step(&mut self, py: Python<'_>, dt: f64) -> PyResult<usize> {
        let sim = &mut self.sim;
        let its = py.detach(|| sim.step(dt)).map_err(py_err)?;
        self.warn(py)?;
        Ok(its)
    }

    /// Advances by one step that lands exactly on `t_end` [s] (after the current time).
    fn step_to(&mut self, py: Python<'_>, t_end: f64) -> PyResult<usize> {
        let sim = &mut self.sim;
        let its = py.detach(|| sim.step_to(t_end)).map_err(py_err)?;
        self.warn(py)?;
        Ok(its)
    }

    /// Runs from the current state to `end` [s] in steps of `dt` (default: `time.dt`; a shorter last
    /// step lands on `end` when it is not on the grid) and returns the rows of `results.csv` as a
    /// dict of numpy columns named as its header, the current state first (with a wall, the
    /// contact columns `gap_m`, `contact_force_N`, `contact_J`, `impacts` follow). From the start of
    /// a `Simulation(cfg)` this is the CLI's `results.csv` for `time.end = end`, bit for bit. The GIL
    /// is released; Ctrl-C stops at a step boundary (raising `KeyboardInterrupt`).
    #[pyo3(signature = (end, dt=None))]
    fn run<'py>(&mut self, py: Python<'py>, end: f64, dt: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
        let dt = dt.unwrap_or(self.config.time.dt);
        let t0 = self.sim.time();
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "run: dt = {dt} s; allowed dt > 0 and finite"
            )));
        }
        if !(end >= t0 && end.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "run: end = {end} s is before the current time {t0} s"
            )));
        }
        // the run driver's steps: of dt, a shortened last one landing on `end`
        let steps = PlanSteps::from_now(&self.sim, dt, end);
        // Ctrl-C reaches the main thread only: there, look for it every SIGNAL_CHECK of wall time
        // (each look takes the GIL back for a moment); elsewhere never
        let threading = py.import("threading")?;
        let main_thread = threading
            .call_method0("current_thread")?
            .is(&threading.call_method0("main_thread")?);
        let sim = &mut self.sim;
        let rows = py.detach(|| -> PyResult<Vec<Vec<f64>>> {
            let mut rows = Vec::with_capacity(steps.plan.steps() + 1);
            let mut interrupt = None;
            let mut looked = std::time::Instant::now();
            let stop = || {
                if main_thread && looked.elapsed() >= SIGNAL_CHECK {
                    interrupt = Python::attach(|py| py.check_signals()).err();
                    looked = std::time::Instant::now();
                }
                interrupt.is_some()
            };
            let (_, walked) = steps.walk(
                sim,
                |_, record| {
                    rows.push(csv_values(record));
                    Ok(())
                },
                stop,
            );
            if let Some(e) = interrupt {
                return Err(e);
            }
            walked.map_err(py_err)?;
            Ok(rows)
        })?;
        self.warn(py)?;
        let columns = PyDict::new(py);
        let header = pendulum_fem_run::rows::header(self.sim.model.wall.is_some());
        for (j, name) in header.split(',').enumerate() {
            let column: Vec<f64> = rows.iter().map(|r| r[j]).collect();
            columns.set_item(name, PyArray1::from_vec(py, column))?;
        }
        Ok(columns)
    }

    /// The complete state as bytes (`pendulum_fem`'s snapshot format): `restore` makes the steps
    /// after it bit for bit those of the simulation that never left.
    fn snapshot<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.sim.snapshot().to_bytes())
    }

    /// Restores a `snapshot()` of a simulation of the same model (configuration and mesh; a damaged
    /// or foreign snapshot is a `ValueError`).
    fn restore(&mut self, data: &[u8]) -> PyResult<()> {
        let snap = Snapshot::from_bytes(data, "snapshot").map_err(py_err)?;
        self.sim.restore(&snap).map_err(py_err)
    }

    /// A reduced body's largest error estimate so far and when it was reached, `(eta, t)`
    /// (dimensionless, s): the relative error of its elastic forces against the full model's;
    /// above 0.01 it warns once (a `UserWarning`). `None` for the full model.
    #[getter]
    fn error_estimate(&self) -> Option<(f64, f64)> {
        self.sim.error_estimate()
    }

    /// Time of the current state [s].
    #[getter]
    fn time(&self) -> f64 {
        self.sim.time()
    }

    /// Proxy angle (best-fit rotation about the pivot) [rad], counter-clockwise from hanging down,
    /// unwrapped.
    #[getter]
    fn theta(&self) -> f64 {
        self.sim.theta()
    }

    /// Best-fit angular velocity [rad/s].
    #[getter]
    fn omega(&mut self) -> f64 {
        self.sim.angular_rates().0
    }

    /// Best-fit angular acceleration [rad/s²] (depends on the torque held now).
    #[getter]
    fn alpha(&mut self) -> f64 {
        self.sim.angular_rates().1
    }

    /// Pivot torque [N m], counter-clockwise positive: the value held since it was last set, else the
    /// `[torque]` profile's value now (0 without one). Setting it holds the value over the following
    /// steps; on a model without a torque profile, setting it before the first step declares a
    /// torque input (`torque.profile = "constant"`).
    #[getter]
    fn tau(&self) -> f64 {
        self.sim
            .held_torque()
            .unwrap_or_else(|| self.sim.model.applied_torque(self.sim.time(), self.sim.held_torque()))
    }

    #[setter]
    fn set_tau(&mut self, py: Python<'_>, value: f64) -> PyResult<()> {
        if self.sim.model.torque.is_none() {
            self.declare_torque_input(py)?;
        }
        self.sim.set_torque(value).map_err(py_err)
    }

    /// Gap between the head and the wall face [m], positive while apart. With a wall: the
    /// stepper's smallest gap of the head's arc to the face (negative: the largest penetration),
    /// the `gap_m` column of `results.csv`; without one: the head's distance to the plane
    /// `x = wall.x`.
    #[getter]
    fn gap(&self) -> f64 {
        self.sim.gap()
    }

    /// Normal force of the wall on the head [N] (the `contact_force_N` column; 0 without a wall).
    #[getter]
    fn contact_force(&self) -> f64 {
        self.sim.contact_force()
    }

    /// Impacts of the head on the wall so far (counted when the head first penetrates the wall;
    /// the `impacts` column). The parity of this count is the event indicator for a co-simulation
    /// master: an impact may start and end between two communication points.
    #[getter]
    fn impacts(&self) -> usize {
        self.sim.impacts()
    }

    /// Whether the head is in an impact now (from its first penetration until the stepper ends it).
    #[getter]
    fn in_contact(&self) -> bool {
        self.sim.in_contact()
    }

    /// The contact events so far, the rows of the CLI's `events.csv`: a list of dicts with its
    /// columns as keys: `time_s`, `event` (`"impact_start"` or `"impact_end"`), `theta_rad`,
    /// `omega_rad_s`, `impulse_N_s`, `max_penetration_m` and `max_force_N` (0 at a start). Empty
    /// without a wall.
    #[getter]
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let keys: Vec<&str> = EVENTS_HEADER.split(',').collect();
        let list = PyList::empty(py);
        for e in self.sim.contact_events() {
            let row = PyDict::new(py);
            row.set_item(keys[0], e.time)?;
            row.set_item(keys[1], pendulum_fem_run::rows::event_name(e.kind))?;
            row.set_item(keys[2], e.theta)?;
            row.set_item(keys[3], e.omega)?;
            row.set_item(keys[4], e.impulse)?;
            row.set_item(keys[5], e.penetration)?;
            row.set_item(keys[6], e.force)?;
            list.append(row)?;
        }
        Ok(list)
    }

    /// Energies of the current state [J]: `kinetic`, `strain`, `gravity` (relative to the pivot
    /// height), `contact` (the wall's penalty energy, 0 without a wall), `total` (their sum) and
    /// `torque_work` (work of the torque since the start).
    #[getter]
    fn energies<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let e = self.sim.energies();
        let d = PyDict::new(py);
        d.set_item("kinetic", e.kinetic)?;
        d.set_item("strain", e.strain)?;
        d.set_item("gravity", e.gravity)?;
        d.set_item("contact", e.contact)?;
        d.set_item("total", e.total)?;
        d.set_item("torque_work", e.torque_work)?;
        Ok(d)
    }

    /// Force of the hinge on the body `(fx, fy)` [N].
    #[getter]
    fn hinge_reaction(&self) -> (f64, f64) {
        let [x, y] = self.sim.hinge_reaction();
        (x, y)
    }

    /// Steps taken since the start.
    #[getter]
    fn steps(&self) -> usize {
        self.sim.step
    }

    /// Newton iterations of the last step.
    #[getter]
    fn newton_iterations(&self) -> usize {
        self.sim.last_newton_iterations()
    }

    /// Reference node coordinates, shape `(nodes, 2)` [m] (pivot at the origin, the body hanging
    /// along −y; six-node triangles: vertices first, then mid-edge nodes).
    #[getter]
    fn nodes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = self.sim.model.mesh.nodes.iter().flatten().copied().collect();
        Self::pairs(py, &flat)
    }

    /// Triangles as node indices, shape `(triangles, 6)`: vertices counter-clockwise, then the
    /// mid-edge nodes of the edges 0→1, 1→2, 2→0.
    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let tris = &self.sim.model.mesh.triangles;
        let flat: Vec<i64> = tris.iter().flatten().map(|&n| n as i64).collect();
        PyArray1::from_vec(py, flat).reshape([tris.len(), 6])
    }

    /// Nodal displacement, shape `(nodes, 2)` [m] (a copy).
    #[getter]
    fn displacement<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        Self::pairs(py, self.sim.displacement())
    }

    /// Nodal velocity, shape `(nodes, 2)` [m/s] (a copy).
    #[getter]
    fn velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        Self::pairs(py, self.sim.velocity())
    }

    /// Nodal von Mises stress, shape `(nodes,)` [Pa] (computed on access).
    #[getter]
    fn von_mises<'py>(&mut self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.sim.nodal_stress().von_mises)
    }

    /// Nodal Cauchy stress `[σxx, σyy, σxy]`, shape `(nodes, 3)` [Pa] (computed on access).
    #[getter]
    fn cauchy_stress<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = self.sim.nodal_stress().cauchy;
        let n = s.len();
        let flat: Vec<f64> = s.into_iter().flatten().collect();
        PyArray1::from_vec(py, flat).reshape([n, 3])
    }

    /// Mass of the body [kg].
    #[getter]
    fn mass(&self) -> f64 {
        self.sim.model.mass_kg()
    }

    /// Moment of inertia about the pivot [kg m²].
    #[getter]
    fn inertia(&self) -> f64 {
        self.sim.model.inertia_pivot()
    }

    /// Centre of mass of the reference (hanging) body `(x, y)` [m], pivot at the origin: the moment
    /// of gravity at a rigid rotation θ is `−m g d sin θ` with `d = |centre of mass|`.
    #[getter]
    fn center_of_mass(&self) -> (f64, f64) {
        let p = &self.sim.model.projection;
        (p.first_moment[0] / p.area, p.first_moment[1] / p.area)
    }

    /// The configuration in effect, as a dict of sections (a torque input declared by setting
    /// `tau` shows as `torque.profile = "constant"`).
    #[getter]
    fn config<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let json = serde_json::to_string(&self.config).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        py.import("json")?.call_method1("loads", (json,))
    }

    /// The configuration in effect as TOML (for `pendulum-fem run --config`).
    #[getter]
    fn config_toml(&self) -> PyResult<String> {
        config_toml(&self.config)
    }

    fn __repr__(&self) -> String {
        format!(
            "<pendulum_fem.Simulation t={} s, theta={:.6} rad, {} nodes, {} triangles>",
            self.sim.time(),
            self.sim.theta(),
            self.sim.model.mesh.num_nodes(),
            self.sim.model.mesh.triangles.len()
        )
    }
}
