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
//! * **FMU states** ([`FmuState`]) are a [`Snapshot`] plus the held input, the impact flag, the
//!   last internal step and the start time (the impact count is the stepper's, in the snapshot);
//!   serialised behind a small header, all of it under one checksum ([`FmuState::to_bytes`]).

use pendulum_fem_core::simulation::split;
use pendulum_fem_core::{mesh, Config, Error, Simulation, Snapshot};

use crate::contact::contact_outputs;
use crate::variables::{Causality, Kind, Output, Role, Variable, VARIABLES};

/// FMI 2.0 status codes.
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
            Self::Terminated => "terminated",
            Self::Error => "error",
        }
    }
}

/// The phases in which values can be read (`fmi2Get*`).
pub const GET_PHASES: &[Phase] = &[Phase::Initialization, Phase::StepMode, Phase::Terminated];

/// The phases in which some values can be set (`fmi2Set*`): parameters before
/// `fmi2ExitInitializationMode`, the input until `fmi2Terminate`.
pub const SET_PHASES: &[Phase] = &[Phase::Instantiated, Phase::Initialization, Phase::StepMode];

/// Every phase but [`Phase::Error`].
pub const LIVE_PHASES: &[Phase] = &[
    Phase::Instantiated,
    Phase::Initialization,
    Phase::StepMode,
    Phase::Terminated,
];

/// Receives log messages: `(status, category, message)`.
pub type LogSink = Box<dyn Fn(Status, &str, &str)>;

/// The state of an instance that `fmi2GetFMUstate` saves.
#[derive(Clone, Debug, PartialEq)]
pub struct FmuState {
    /// The simulation's complete state.
    pub snapshot: Snapshot,
    /// The held torque input \[N m\].
    pub tau: f64,
    /// An impact started during the last step.
    pub impact: bool,
    /// The internal step of the last `doStep` \[s\] (it decides the next one's rounding).
    pub last_internal_step: Option<f64>,
    /// `startTime` of `fmi2SetupExperiment` \[s\]: the FMU time is this plus the snapshot's.
    pub start_time: f64,
}

const STATE_MAGIC: &[u8; 8] = b"PFEMFMU3";

/// Bytes before the snapshot: magic, `tau`, `impact`, last internal step, start time.
const STATE_HEAD: usize = 8 + 8 + 1 + 8 + 8;

/// 64-bit FNV-1a, the checksum of a serialized FMU state.
fn checksum(bytes: &[u8]) -> u64 {
    crate::variables::fnv1a(bytes, 0xcbf2_9ce4_8422_2325)
}

impl FmuState {
    /// Little-endian:
    ///
    /// ```text
    /// "PFEMFMU3"  magic (8 bytes)
    /// f64         tau (IEEE bits)
    /// u8          impact (0/1)
    /// f64         the last internal step (NaN for none)
    /// f64         start time
    /// …           Snapshot::to_bytes (with its own checksum)
    /// u64         FNV-1a of every byte before it
    /// ```
    ///
    /// The checksum covers the header too: a flipped bit anywhere is refused by
    /// [`FmuState::from_bytes`].
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut b = STATE_MAGIC.to_vec();
        b.extend_from_slice(&self.tau.to_bits().to_le_bytes());
        b.push(u8::from(self.impact));
        let last = self.last_internal_step.unwrap_or(f64::NAN);
        b.extend_from_slice(&last.to_bits().to_le_bytes());
        b.extend_from_slice(&self.start_time.to_bits().to_le_bytes());
        b.extend_from_slice(&self.snapshot.to_bytes());
        let sum = checksum(&b);
        b.extend_from_slice(&sum.to_le_bytes());
        b
    }

    /// Reads [`FmuState::to_bytes`]; a damaged, truncated or foreign buffer is an error.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, Error> {
        let refuse = |why: String| {
            Err(Error::Input(format!(
                "serialized FMU state of {} bytes: {why}",
                bytes.len()
            )))
        };
        if bytes.len() < 8 || &bytes[..8] != STATE_MAGIC {
            let older = bytes.len() >= 8 && bytes.starts_with(b"PFEMFMU");
            return refuse(if older {
                format!(
                    "format {} of another version of this FMU; this one reads {}",
                    String::from_utf8_lossy(&bytes[..8]),
                    String::from_utf8_lossy(STATE_MAGIC)
                )
            } else {
                "it does not start with PFEMFMU3 (not made by this FMU)".into()
            });
        }
        if bytes.len() < STATE_HEAD + 8 {
            return refuse("truncated".into());
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        if checksum(body) != u64::from_le_bytes(sum.try_into().expect("8 bytes")) {
            return refuse("damaged (its checksum does not match its bytes)".into());
        }
        let f64_at = |i: usize| f64::from_bits(u64::from_le_bytes(body[i..i + 8].try_into().expect("8 bytes")));
        let tau = f64_at(8);
        let impact = match body[16] {
            0 => false,
            1 => true,
            other => return refuse(format!("impact flag {other}, allowed 0 or 1")),
        };
        let last = f64_at(17);
        let start_time = f64_at(25);
        if !tau.is_finite() || !start_time.is_finite() || !(last.is_nan() || (last.is_finite() && last > 0.0)) {
            return refuse(format!(
                "tau = {tau}, last internal step = {last}, start time = {start_time}: not a state of this FMU"
            ));
        }
        let snapshot = Snapshot::from_bytes(&body[STATE_HEAD..], "serialized FMU state")?;
        Ok(Self {
            snapshot,
            tau,
            impact,
            last_internal_step: (!last.is_nan()).then_some(last),
            start_time,
        })
    }
}

/// One FMU instance (see the module doc).
pub struct Instance {
    /// The instance name given by the master.
    pub name: String,
    /// Whether debug logging (non-error messages) is on.
    pub logging_on: bool,
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
    /// A new instance with every variable at its start value.
    pub fn new(name: &str, logging_on: bool, log: LogSink) -> Self {
        Self {
            name: name.to_string(),
            logging_on,
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
                "{function}: not allowed in the error state ({why}); only fmi2Reset or fmi2FreeInstance leave it"
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

    /// Logs an error (always) and returns [`Status::Error`].
    pub fn error(&self, message: &str) -> Status {
        (self.log)(Status::Error, "logStatusError", message);
        Status::Error
    }

    /// Logs an informative message when logging is on.
    fn info(&self, message: &str) {
        if self.logging_on {
            (self.log)(Status::Ok, "logAll", message);
        }
    }

    /// The current value of the table entry with this role.
    fn value_of(&self, role: Role) -> f64 {
        let i = VARIABLES
            .iter()
            .position(|v| v.role == role)
            .expect("role in the table");
        self.values[i]
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
        *self = Self::new(&name, logging_on, log);
    }

    /// `fmi2SetupExperiment`: the start time (tolerance and stop time are not used).
    pub fn setup_experiment(&mut self, start_time: f64) -> Status {
        if let Err(status) = self.check_phase("fmi2SetupExperiment", &[Phase::Instantiated]) {
            return status;
        }
        if !start_time.is_finite() {
            return self.error(&format!("fmi2SetupExperiment: startTime = {start_time} is not finite"));
        }
        self.start_time = start_time;
        Status::Ok
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization(&mut self) -> Status {
        if let Err(status) = self.check_phase("fmi2EnterInitializationMode", &[Phase::Instantiated]) {
            return status;
        }
        self.phase = Phase::Initialization;
        Status::Ok
    }

    /// `fmi2ExitInitializationMode`: builds the simulation; invalid parameters are reported here.
    pub fn exit_initialization(&mut self) -> Status {
        if let Err(status) = self.check_phase("fmi2ExitInitializationMode", &[Phase::Initialization]) {
            return status;
        }
        if let Err(status) = self.ensure_sim() {
            return status;
        }
        self.phase = Phase::StepMode;
        Status::Ok
    }

    /// `fmi2Terminate`: from step mode only (FMI 2.0 allows it after a step, not before
    /// initialisation, nor twice).
    pub fn terminate(&mut self) -> Status {
        if let Err(status) = self.check_phase("fmi2Terminate", &[Phase::StepMode]) {
            return status;
        }
        self.phase = Phase::Terminated;
        Status::Ok
    }

    /// The configuration of the current parameter values: the CLI's defaults, each parameter with a
    /// configuration key set by name, `initial.angle_deg` from `theta_start`, and the torque input
    /// declared (`[torque] profile = "constant", amplitude = 0`).
    pub fn config(&self) -> Result<Config, Error> {
        let mut sets = Vec::new();
        for (v, &value) in VARIABLES.iter().zip(&self.values) {
            match v.role {
                Role::Config(key) => sets.push(match v.kind {
                    Kind::Real => format!("{key}={value:?}"),
                    _ => format!("{key}={}", value as i64),
                }),
                Role::ThetaStart => sets.push(format!("initial.angle_deg={:?}", value.to_degrees())),
                Role::MaxCutbacks => sets.push(match value as i64 {
                    -1 => "solver.max_cutbacks=\"auto\"".to_string(),
                    count => format!("solver.max_cutbacks={count}"),
                }),
                Role::WallKind => sets.push(match value as i64 {
                    0 => "wall.kind=\"none\"".to_string(),
                    1 => "wall.kind=\"rigid\"".to_string(),
                    2 => "wall.kind=\"deformable\"".to_string(),
                    other => format!("wall.kind={other}"),
                }),
                _ => {}
            }
        }
        Config::load(None, &sets).map(|c| c.with_torque_input())
    }

    /// Checks the parameters that are not configuration keys.
    fn check_own_parameters(&self) -> Result<(), String> {
        let h = self.value_of(Role::MaxInternalStep);
        if !(h > 0.0 && h.is_finite()) {
            return Err(format!("max_internal_step = {h}: allowed a finite value > 0 s"));
        }
        let w = self.value_of(Role::WallKind);
        if !(0.0..=2.0).contains(&w) {
            return Err(format!(
                "wall_kind = {w}: allowed 0 (none), 1 (rigid) or 2 (deformable)"
            ));
        }
        let t = self.value_of(Role::ThetaStart);
        if !(-2.0 * std::f64::consts::PI..=2.0 * std::f64::consts::PI).contains(&t) {
            return Err(format!("theta_start = {t}: allowed -2 pi to 2 pi rad"));
        }
        Ok(())
    }

    /// Builds the simulation if there is none or a parameter changed; errors are logged.
    fn ensure_sim(&mut self) -> Result<(), Status> {
        if self.sim.is_some() && !self.stale {
            return Ok(());
        }
        if let Err(e) = self.check_own_parameters() {
            return Err(self.error(&format!("invalid parameter: {e}")));
        }
        let built = self.config().and_then(|cfg| {
            let mesh = mesh::generate(&cfg)?;
            let mut sim = Simulation::from_config(&cfg, mesh)?;
            let tau = self.value_of(Role::Tau);
            if tau != 0.0 {
                sim.set_torque(tau)?;
            }
            Ok(sim)
        });
        match built {
            Ok(sim) => {
                self.info(&format!(
                    "model built: {} triangles, {} nodes, theta = {} rad",
                    sim.model.mesh.triangles.len(),
                    sim.model.mesh.num_nodes(),
                    sim.theta()
                ));
                self.sim = Some(sim);
                self.invalidate();
                self.stale = false;
                Ok(())
            }
            Err(e) => {
                self.sim = None;
                Err(self.error(&format!("invalid parameters, the model cannot be built: {e}")))
            }
        }
    }

    /// Sets values by value reference (`fmi2SetReal`, `…Integer`, `…Boolean`): parameters in the
    /// instantiated state and initialization mode, the input `tau` until `fmi2Terminate`.
    pub fn set(&mut self, kind: Kind, vrs: &[u32], values: &[f64]) -> Status {
        let function = match kind {
            Kind::Real => "fmi2SetReal",
            Kind::Integer => "fmi2SetInteger",
            Kind::Boolean => "fmi2SetBoolean",
        };
        if let Err(status) = self.check_phase(function, SET_PHASES) {
            return status;
        }
        self.invalidate();
        for (&vr, &value) in vrs.iter().zip(values) {
            let Some((i, v)) = crate::variables::lookup(vr, kind) else {
                return self.error(&format!("{function}: no {kind:?} variable with value reference {vr}"));
            };
            match v.causality {
                Causality::Output => return self.error(&format!("{function}: {} is an output", v.name)),
                Causality::Parameter if !matches!(self.phase, Phase::Instantiated | Phase::Initialization) => {
                    return self.error(&format!(
                        "{function}: {} is a fixed parameter, not settable in the {} state; set it before \
                         fmi2ExitInitializationMode",
                        v.name,
                        self.phase.name()
                    ));
                }
                Causality::Parameter => {
                    if self.values[i].to_bits() != value.to_bits() {
                        self.stale = true;
                    }
                    self.values[i] = value;
                }
                Causality::Input => {
                    if !value.is_finite() {
                        return self.error(&format!("{function}: {} = {value} is not finite", v.name));
                    }
                    let changed = self.values[i].to_bits() != value.to_bits();
                    // a refused input leaves the held one in place
                    if let (true, Some(sim), false) = (changed, self.sim.as_mut(), self.stale) {
                        if let Err(e) = sim.set_torque(value) {
                            let t = self.time();
                            return self.error(&format!("{function}: tau = {value} N.m at t = {t} s: {e}"));
                        }
                    }
                    self.values[i] = value;
                }
            }
        }
        Status::Ok
    }

    /// Reads values by value reference (`fmi2GetReal`, `…Integer`, `…Boolean`) into `out`: from
    /// initialization mode on (FMI 2.0 does not allow it in the instantiated state).
    pub fn get(&mut self, kind: Kind, vrs: &[u32], out: &mut [f64]) -> Status {
        let function = match kind {
            Kind::Real => "fmi2GetReal",
            Kind::Integer => "fmi2GetInteger",
            Kind::Boolean => "fmi2GetBoolean",
        };
        if let Err(status) = self.check_phase(function, GET_PHASES) {
            return status;
        }
        for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
            let Some((i, v)) = crate::variables::lookup(vr, kind) else {
                return self.error(&format!("{function}: no {kind:?} variable with value reference {vr}"));
            };
            *slot = match v.role {
                Role::Output(which) => match self.output(which) {
                    Ok(value) => value,
                    Err(status) => return status,
                },
                _ => self.values[i],
            };
        }
        Status::Ok
    }

    /// One output of the current state, computed on the first request after a change of the state
    /// (a step, a torque input, a restored state) and kept until the next: a master that reads
    /// every output with three calls (Real, Integer, Boolean) pays for each once.
    fn output(&mut self, which: Output) -> Result<f64, Status> {
        if let Some(value) = self.cache[which as usize] {
            return Ok(value);
        }
        self.ensure_sim()?;
        let impact = self.impact;
        let sim = self.sim.as_mut().expect("built above");
        let cache = &mut self.cache;
        match which {
            Output::Theta => cache[Output::Theta as usize] = Some(sim.theta()),
            Output::Omega | Output::Alpha => {
                let (omega, alpha) = sim.angular_rates();
                cache[Output::Omega as usize] = Some(omega);
                cache[Output::Alpha as usize] = Some(alpha);
            }
            Output::TotalEnergy => cache[Output::TotalEnergy as usize] = Some(sim.energies().total),
            Output::Gap | Output::ContactForce | Output::ContactCount | Output::Impact => {
                let c = contact_outputs(sim, impact);
                cache[Output::Gap as usize] = Some(c.gap);
                cache[Output::ContactForce as usize] = Some(c.force);
                cache[Output::ContactCount as usize] = Some(f64::from(c.count));
                cache[Output::Impact as usize] = Some(f64::from(u8::from(c.impact)));
            }
        }
        Ok(self.cache[which as usize].expect("computed above"))
    }

    /// Forgets the computed outputs (the state or an input changed).
    fn invalidate(&mut self) {
        self.cache = [None; OUTPUTS];
    }

    /// `fmi2DoStep(t, h)` (see the module doc).
    pub fn do_step(&mut self, t: f64, h: f64) -> Status {
        if let Err(status) = self.check_phase("fmi2DoStep", &[Phase::StepMode]) {
            return status;
        }
        let now = self.time();
        if !(h >= 0.0 && h.is_finite()) {
            return self.error(&format!(
                "fmi2DoStep at t = {now} s: communicationStepSize = {h} s; allowed a finite value >= 0 s"
            ));
        }
        // NaN is never within
        let within = (t - now).abs() <= TIME_TOLERANCE * now.abs().max(1.0);
        if !within {
            return self.error(&format!(
                "fmi2DoStep: currentCommunicationPoint = {t} s is not the FMU's time {now} s (tolerance {TIME_TOLERANCE} relative)"
            ));
        }
        if h == 0.0 {
            // an output refresh: outputs are computed on request from the current state
            return Status::Ok;
        }
        let max_step = self.value_of(Role::MaxInternalStep);
        let (n, sub) = match split::internal_steps(h, max_step, self.last_internal_step) {
            Ok(split) => split,
            Err(e) => return self.error(&format!("fmi2DoStep from t = {now} s by h = {h} s refused: {e}")),
        };
        let sim = self.sim.as_mut().expect("built at exitInitializationMode");
        let before = (n > 1).then(|| sim.snapshot());
        let impacts_before = sim.impacts();
        for k in 0..n {
            if let Err(e) = sim.step(sub) {
                let failed_at = self.start_time + sim.time();
                if let Some(before) = &before {
                    sim.restore(before).expect("a snapshot of this model restores");
                }
                return self.error(&format!(
                    "fmi2DoStep from t = {now} s by h = {h} s failed in internal step {} of {n} at t = {failed_at} s \
                     (the state is as before the call): {e}",
                    k + 1
                ));
            }
        }
        self.last_internal_step = Some(sub);
        self.impact = sim.impacts() > impacts_before;
        self.invalidate();
        Status::Ok
    }

    /// The state for `fmi2GetFMUstate`.
    pub fn get_state(&self) -> Result<FmuState, Status> {
        self.check_phase("fmi2GetFMUstate", LIVE_PHASES)?;
        let Some(sim) = self.sim.as_ref().filter(|_| !self.stale) else {
            return Err(self.error("fmi2GetFMUstate: the model is not built yet (after fmi2ExitInitializationMode)"));
        };
        Ok(FmuState {
            snapshot: sim.snapshot(),
            tau: self.value_of(Role::Tau),
            impact: self.impact,
            last_internal_step: self.last_internal_step,
            start_time: self.start_time,
        })
    }

    /// `fmi2SetFMUstate`: a state of this model (same parameters) only. The phase stays (FMI 2.0:
    /// setting a state is no transition; in the instantiated state the master still initialises).
    pub fn set_state(&mut self, state: &FmuState) -> Status {
        if let Err(status) = self.check_phase("fmi2SetFMUstate", LIVE_PHASES) {
            return status;
        }
        if let Err(status) = self.ensure_sim() {
            return status;
        }
        let sim = self.sim.as_mut().expect("built above");
        if let Err(e) = sim.restore(&state.snapshot) {
            return self.error(&format!("fmi2SetFMUstate: {e}"));
        }
        let tau = VARIABLES.iter().position(|v| v.role == Role::Tau).expect("tau");
        self.values[tau] = state.tau;
        self.impact = state.impact;
        self.last_internal_step = state.last_internal_step;
        self.start_time = state.start_time;
        self.invalidate();
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
