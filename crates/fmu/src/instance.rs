//! One FMU instance in safe Rust: parameter and input values, the simulation built from them, the
//! FMI 2.0 Co-Simulation state machine, `doStep`, and FMU states. The C interface (module `ffi`)
//! only converts arguments and catches panics; everything an FMI call means happens here.
//!
//! * **Parameters** (table [`VARIABLES`]) are applied as configuration overrides by name, with
//!   `[torque] profile = "constant", amplitude = 0` declared so that `tau` is an input of the
//!   stepper ([`Instance::config`]). The simulation is built when first needed (an output read in
//!   initialisation mode, or `fmi2ExitInitializationMode`) and built again if a parameter changed
//!   meanwhile; an invalid parameter fails there with the configuration's message naming the key.
//! * **The state machine** ([`Phase`]): every call checks that the FMI 2.0 Co-Simulation state
//!   machine allows it in the current phase; a call it forbids returns `fmi2Error` with a logged
//!   message naming the function and the phase, and changes nothing. A panic caught at the C
//!   boundary puts the instance into [`Phase::Error`], which only `fmi2Reset` and
//!   `fmi2FreeInstance` leave (the panic may have left the state half-updated).
//! * **`doStep(t, h)`**: the master's `t` is accepted when it is within 1e-6 (relative, at least
//!   1e-6 s absolute) of the FMU's time; the FMU keeps its own clock. `h = 0` refreshes the outputs.
//!   Otherwise `h` is split into internal steps by [`split::internal_steps`] (the rule the Python
//!   package uses too): `n = ⌈h / max_internal_step⌉` equal steps, so with `h = max_internal_step`
//!   it is one `Simulation::step(h)`, bit for bit the CLI's step, a master's rounding of `h`
//!   absorbed, and a step that would take more than [`split::MAX_INTERNAL_STEPS`] refused. A failed
//!   internal step leaves the state as it was before the whole `doStep` (a snapshot taken before a
//!   multi-step `doStep` is restored; a single step is rolled back by the stepper itself).
//! * **FMI 3.0** ([`Api::Fmi3`], made by [`Instance::new_fmi3`]): the same instance behind the
//!   `fmi3*` functions, with event mode ([`Phase::EventMode`]) and impacts as events: early return
//!   at an impact's start, discrete outputs updated in event mode (module `events`).
//! * **FMU states** ([`FmuState`]) are a [`Snapshot`] plus the held input, the impact flag, the
//!   last internal step and the start time (the impact count is the stepper's, in the snapshot);
//!   serialised behind a small header, all of it under one checksum ([`FmuState::to_bytes`]).

mod events;
mod fmu_state;
mod parameters;
mod stepping;

pub use events::{EventSettings, StepEnd};
pub use fmu_state::FmuState;

use pendulum_fem_core::Simulation;

use crate::variables::{Variable, VARIABLES};

// only named in the documentation's links
#[cfg(doc)]
use crate::variables::Output;
#[cfg(doc)]
use pendulum_fem_core::{simulation::split, Snapshot};

/// The FMI version whose C interface an instance serves: it names the functions in messages and
/// decides the state machine's event mode and the impact events ([`EventSettings`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Api {
    /// FMI 2.0 Co-Simulation (`fmi2*`).
    Fmi2,
    /// FMI 3.0 Co-Simulation (`fmi3*`).
    Fmi3,
}

impl Api {
    /// The prefix of the standard's function names.
    pub fn prefix(self) -> &'static str {
        match self {
            Self::Fmi2 => "fmi2",
            Self::Fmi3 => "fmi3",
        }
    }

    /// The name (without prefix) of `op` (`"Get"`, `"Set"`) on an FMU state: FMI 2.0 writes
    /// `FMUstate`, FMI 3.0 `FMUState`.
    pub fn state_call(self, op: &str) -> &'static str {
        match (self, op) {
            (Self::Fmi2, "Get") => "GetFMUstate",
            (Self::Fmi2, _) => "SetFMUstate",
            (Self::Fmi3, "Get") => "GetFMUState",
            (Self::Fmi3, _) => "SetFMUState",
        }
    }
}

/// FMI 2.0 status codes (FMI 3.0 has the same ones but `Pending`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(i32)]
pub enum Status {
    /// `fmi2OK`.
    Ok = 0,
    /// `fmi2Warning`.
    Warning = 1,
    /// `fmi2Discard`.
    Discard = 2,
    /// `fmi2Error`.
    Error = 3,
    /// `fmi2Fatal`.
    Fatal = 4,
    /// `fmi2Pending`.
    Pending = 5,
}

/// Where an instance is in the FMI 2.0 Co-Simulation state machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// After `fmi2Instantiate` (or `fmi2Reset`).
    Instantiated,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    Initialization,
    /// Stepping.
    StepMode,
    /// FMI 3.0 only: between `fmi3EnterEventMode` (or `fmi3ExitInitializationMode` with event
    /// mode used) and `fmi3EnterStepMode`.
    EventMode,
    /// After `fmi2Terminate`.
    Terminated,
    /// After a caught panic ([`Instance::enter_error_state`]): only `fmi2Reset` and
    /// `fmi2FreeInstance` are allowed.
    Error,
}

impl Phase {
    /// The phase as messages name it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Instantiated => "instantiated",
            Self::Initialization => "initialization mode",
            Self::StepMode => "step mode",
            Self::EventMode => "event mode",
            Self::Terminated => "terminated",
            Self::Error => "error",
        }
    }
}

/// The phases in which values can be read (`fmi2Get*`).
pub const GET_PHASES: &[Phase] = &[
    Phase::Initialization,
    Phase::StepMode,
    Phase::EventMode,
    Phase::Terminated,
];

/// The phases in which some values can be set (`fmi2Set*`): parameters before
/// `fmi2ExitInitializationMode`, the input until `fmi2Terminate`.
pub const SET_PHASES: &[Phase] = &[
    Phase::Instantiated,
    Phase::Initialization,
    Phase::StepMode,
    Phase::EventMode,
];

/// Every phase but [`Phase::Error`].
pub const LIVE_PHASES: &[Phase] = &[
    Phase::Instantiated,
    Phase::Initialization,
    Phase::StepMode,
    Phase::EventMode,
    Phase::Terminated,
];

/// Receives log messages: `(status, category, message)`.
pub type LogSink = Box<dyn Fn(Status, &str, &str)>;

/// One FMU instance (see the module doc).
pub struct Instance {
    /// The instance name given by the master.
    pub name: String,
    /// Whether debug logging (non-error messages) is on.
    pub logging_on: bool,
    /// The C interface served.
    pub api: Api,
    /// FMI 3.0: event mode, early return and the impacts announced (`None` for FMI 2.0).
    events: Option<events::Events>,
    log: LogSink,
    /// The state machine.
    pub phase: Phase,
    /// Value of every table entry (Integer and Boolean as 0/1), in table order.
    values: Vec<f64>,
    /// The simulation, once built.
    sim: Option<Simulation>,
    /// Parameters changed since the simulation was built.
    stale: bool,
    /// `startTime` of `fmi2SetupExperiment` \[s\]; the FMU time is this plus the simulation's.
    start_time: f64,
    /// An impact started during the last step.
    impact: bool,
    /// The internal step of the last `doStep` \[s\] (see [`split::internal_steps`]).
    last_internal_step: Option<f64>,
    /// Outputs computed for the current state, by [`Output`] as index.
    cache: [Option<f64>; OUTPUTS],
    /// Why the instance is in [`Phase::Error`].
    failure: Option<String>,
    /// A panic the next C call raises ([`Instance::panic_on_next_call`], tests only).
    pub(crate) test_panic: Option<String>,
}

/// The number of [`Output`]s.
const OUTPUTS: usize = 8;

/// Relative tolerance between the master's communication point and the FMU's time.
pub const TIME_TOLERANCE: f64 = 1e-6;

impl Instance {
    /// A new FMI 2.0 instance with every variable at its start value.
    pub fn new(name: &str, logging_on: bool, log: LogSink) -> Self {
        Self::with_api(name, logging_on, log, None)
    }

    /// A new FMI 3.0 Co-Simulation instance with every variable at its start value.
    pub fn new_fmi3(name: &str, logging_on: bool, log: LogSink, settings: EventSettings) -> Self {
        Self::with_api(name, logging_on, log, Some(settings))
    }

    fn with_api(name: &str, logging_on: bool, log: LogSink, settings: Option<EventSettings>) -> Self {
        Self {
            name: name.to_string(),
            logging_on,
            api: if settings.is_some() { Api::Fmi3 } else { Api::Fmi2 },
            events: settings.map(events::Events::new),
            log,
            phase: Phase::Instantiated,
            values: VARIABLES.iter().map(|v| v.start.unwrap_or(0.0)).collect(),
            sim: None,
            stale: true,
            start_time: 0.0,
            impact: false,
            last_internal_step: None,
            cache: [None; OUTPUTS],
            failure: None,
            test_panic: None,
        }
    }

    /// `Ok` when `function` is allowed in the current phase (one of `allowed`); otherwise logs an
    /// error naming the function and the phase (and, in [`Phase::Error`], why the instance is
    /// there) and returns [`Status::Error`].
    pub fn check_phase(&self, function: &str, allowed: &[Phase]) -> Result<(), Status> {
        if allowed.contains(&self.phase) {
            return Ok(());
        }
        if self.phase == Phase::Error {
            let why = self.failure.as_deref().unwrap_or("an earlier call failed");
            return Err(self.error(&format!(
                "{function}: not allowed in the error state ({why}); only {p}Reset or {p}FreeInstance leave it",
                p = self.api.prefix()
            )));
        }
        let names: Vec<&str> = allowed.iter().map(|p| p.name()).collect();
        Err(self.error(&format!(
            "{function}: not allowed in the {} state (allowed in: {})",
            self.phase.name(),
            names.join(", ")
        )))
    }

    /// Puts the instance into [`Phase::Error`] for `reason` (a caught panic): every call but
    /// `fmi2Reset` and `fmi2FreeInstance` is refused from now on, with `reason` in the message.
    pub fn enter_error_state(&mut self, reason: String) {
        self.phase = Phase::Error;
        self.failure = Some(reason);
    }

    /// Makes the next C call on this instance panic with `message` inside the panic guard (tests
    /// of the error state; nothing in the C interface sets it).
    #[doc(hidden)]
    pub fn panic_on_next_call(&mut self, message: &str) {
        self.test_panic = Some(message.to_string());
    }

    /// The standard's name of the function `name` (`"DoStep"` → `fmi2DoStep` or `fmi3DoStep`).
    pub fn call(&self, name: &str) -> String {
        format!("{}{name}", self.api.prefix())
    }

    /// The standard's name of the getter or setter (`op`: `"Get"`, `"Set"`) of values of `kind`:
    /// `fmi2GetReal`, `fmi3GetFloat64`, …
    pub fn typed_call(&self, op: &str, kind: crate::variables::Kind) -> String {
        use crate::variables::Kind;
        let ty = match (self.api, kind) {
            (Api::Fmi2, Kind::Real) => "Real",
            (Api::Fmi3, Kind::Real) => "Float64",
            (Api::Fmi2, Kind::Integer) => "Integer",
            (Api::Fmi3, Kind::Integer) => "Int32",
            (_, Kind::Boolean) => "Boolean",
        };
        self.call(&format!("{op}{ty}"))
    }

    /// Logs an error (always) and returns [`Status::Error`].
    pub fn error(&self, message: &str) -> Status {
        (self.log)(Status::Error, "logStatusError", message);
        Status::Error
    }

    /// Logs the simulation's warning, if it raised one (the reduced body's, once, when it does not
    /// apply), whether logging is on or not: the step still succeeds.
    pub(crate) fn log_warning(&mut self) {
        if let Some(w) = self.sim.as_mut().and_then(|sim| sim.take_warning()) {
            self.warning(&w);
        }
    }

    /// Logs a warning, whether logging is on or not (the call still succeeds).
    fn warning(&self, message: &str) {
        (self.log)(Status::Warning, "logStatusWarning", message);
    }

    /// Logs an informative message when logging is on.
    fn info(&self, message: &str) {
        if self.logging_on {
            (self.log)(Status::Ok, "logAll", message);
        }
    }

    /// The FMU time \[s\].
    pub fn time(&self) -> f64 {
        self.start_time + self.sim.as_ref().map_or(0.0, Simulation::time)
    }

    /// Back to the instantiated state with the start values (`fmi2Reset`; allowed in every phase,
    /// [`Phase::Error`] included).
    pub fn reset(&mut self) {
        let (name, logging_on) = (std::mem::take(&mut self.name), self.logging_on);
        let log = std::mem::replace(&mut self.log, Box::new(|_, _, _| {}));
        let settings = self.events.as_ref().map(|e| e.settings);
        *self = Self::with_api(&name, logging_on, log, settings);
    }

    /// `fmi2SetupExperiment`: the start time (tolerance and stop time are not used).
    pub fn setup_experiment(&mut self, start_time: f64) -> Status {
        let function = self.call(match self.api {
            Api::Fmi2 => "SetupExperiment",
            Api::Fmi3 => "EnterInitializationMode",
        });
        if let Err(status) = self.check_phase(&function, &[Phase::Instantiated]) {
            return status;
        }
        if !start_time.is_finite() {
            return self.error(&format!("{function}: startTime = {start_time} is not finite"));
        }
        self.start_time = start_time;
        Status::Ok
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization(&mut self) -> Status {
        if let Err(status) = self.check_phase(&self.call("EnterInitializationMode"), &[Phase::Instantiated]) {
            return status;
        }
        self.phase = Phase::Initialization;
        Status::Ok
    }

    /// `fmi2ExitInitializationMode`: builds the simulation; invalid parameters are reported here.
    pub fn exit_initialization(&mut self) -> Status {
        if let Err(status) = self.check_phase(&self.call("ExitInitializationMode"), &[Phase::Initialization]) {
            return status;
        }
        if let Err(status) = self.ensure_sim() {
            return status;
        }
        self.phase = Phase::StepMode;
        self.start_events();
        Status::Ok
    }

    /// `fmi2Terminate`: from step mode only (FMI 2.0 allows it after a step, not before
    /// initialisation, nor twice); `fmi3Terminate` from event mode too.
    pub fn terminate(&mut self) -> Status {
        if let Err(status) = self.check_phase(&self.call("Terminate"), &[Phase::StepMode, Phase::EventMode]) {
            return status;
        }
        self.phase = Phase::Terminated;
        Status::Ok
    }

    /// The simulation, once built (for tests and benchmarks).
    pub fn simulation(&mut self) -> Option<&mut Simulation> {
        self.sim.as_mut()
    }

    /// The variable table entry named `name` (for tests).
    pub fn variable(name: &str) -> Option<&'static Variable> {
        crate::variables::by_name(name)
    }
}
