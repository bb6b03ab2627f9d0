//! FMU states: what `fmi2GetFMUstate` saves of an instance ([`FmuState`]), its serialisation under
//! one checksum, and getting and setting an instance's state.

use pendulum_fem_core::{Error, Snapshot};

use super::events::EventState;
use super::{Instance, Status, LIVE_PHASES};
use crate::variables::{Role, VARIABLES};

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
    /// FMI 3.0: the impacts announced, the discrete outputs and the continuation of an early
    /// return (`None` in the FMI 2.0 FMU's states).
    pub events: Option<EventState>,
}

const STATE_MAGIC: &[u8; 8] = b"PFEMFMU3";

/// The magic of an FMI 3.0 instance's state: the FMI 2.0 layout with the event part after the head.
const STATE_MAGIC_FMI3: &[u8; 8] = b"PFEMFMI3";

/// Bytes before the snapshot: magic, `tau`, `impact`, last internal step, start time.
const STATE_HEAD: usize = 8 + 8 + 1 + 8 + 8;

/// 64-bit FNV-1a, the checksum of a serialized FMU state.
fn checksum(bytes: &[u8]) -> u64 {
    pendulum_fem_core::store::fnv1a(bytes)
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
    /// (FMI 3.0 states, magic "PFEMFMI3", only:)
    /// u64, u64    impacts announced, pending for event mode
    /// i32, u8     contact_count, impact (0/1)
    /// u64         length of the continuation (0: none), then its Snapshot::to_bytes
    /// …           Snapshot::to_bytes (with its own checksum)
    /// u64         FNV-1a of every byte before it
    /// ```
    ///
    /// The checksum covers the header too: a flipped bit anywhere is refused by
    /// [`FmuState::from_bytes`].
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut b = match self.events {
            None => STATE_MAGIC.to_vec(),
            Some(_) => STATE_MAGIC_FMI3.to_vec(),
        };
        b.extend_from_slice(&self.tau.to_bits().to_le_bytes());
        b.push(u8::from(self.impact));
        let last = self.last_internal_step.unwrap_or(f64::NAN);
        b.extend_from_slice(&last.to_bits().to_le_bytes());
        b.extend_from_slice(&self.start_time.to_bits().to_le_bytes());
        if let Some(e) = &self.events {
            b.extend_from_slice(&e.announced.to_le_bytes());
            b.extend_from_slice(&e.pending.to_le_bytes());
            b.extend_from_slice(&e.count.to_le_bytes());
            b.push(u8::from(e.impact));
            let continuation = e.continuation.as_ref().map(Snapshot::to_bytes).unwrap_or_default();
            b.extend_from_slice(&(continuation.len() as u64).to_le_bytes());
            b.extend_from_slice(&continuation);
        }
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
        let fmi3 = bytes.len() >= 8 && &bytes[..8] == STATE_MAGIC_FMI3;
        if bytes.len() < 8 || (&bytes[..8] != STATE_MAGIC && !fmi3) {
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
        let (events, at) = if fmi3 {
            match read_events(&body[STATE_HEAD..]) {
                Ok((events, used)) => (Some(events), STATE_HEAD + used),
                Err(why) => return refuse(why),
            }
        } else {
            (None, STATE_HEAD)
        };
        let snapshot = Snapshot::from_bytes(&body[at..], "serialized FMU state")?;
        Ok(Self {
            events,
            snapshot,
            tau,
            impact,
            last_internal_step: (!last.is_nan()).then_some(last),
            start_time,
        })
    }
}

/// Reads the event part of an FMI 3.0 state from the start of `b`: the part and the bytes it took.
fn read_events(b: &[u8]) -> Result<(EventState, usize), String> {
    const FIXED: usize = 8 + 8 + 4 + 1 + 8;
    if b.len() < FIXED {
        return Err("truncated in its event part".into());
    }
    let u64_at = |i: usize| u64::from_le_bytes(b[i..i + 8].try_into().expect("8 bytes"));
    let (announced, pending) = (u64_at(0), u64_at(8));
    let count = i32::from_le_bytes(b[16..20].try_into().expect("4 bytes"));
    let impact = match b[20] {
        0 => false,
        1 => true,
        other => return Err(format!("impact output {other}, allowed 0 or 1")),
    };
    let len = usize::try_from(u64_at(21)).unwrap_or(usize::MAX);
    if len > b.len() - FIXED {
        return Err(format!("continuation of {len} bytes, longer than the state"));
    }
    let continuation = match len {
        0 => None,
        _ => Some(
            Snapshot::from_bytes(&b[FIXED..FIXED + len], "continuation in a serialized FMU state")
                .map_err(|e| e.to_string())?,
        ),
    };
    let events = EventState {
        announced,
        pending,
        count,
        impact,
        continuation,
    };
    Ok((events, FIXED + len))
}

impl Instance {
    /// The state for `fmi2GetFMUstate`.
    pub fn get_state(&self) -> Result<FmuState, Status> {
        let function = self.call(self.api.state_call("Get"));
        self.check_phase(&function, LIVE_PHASES)?;
        let Some(sim) = self.sim.as_ref().filter(|_| !self.stale) else {
            return Err(self.error(&format!(
                "{function}: the model is not built yet (after {}ExitInitializationMode)",
                self.api.prefix()
            )));
        };
        Ok(FmuState {
            snapshot: sim.snapshot(),
            tau: self.value_of(Role::Tau),
            impact: self.impact,
            last_internal_step: self.last_internal_step,
            start_time: self.start_time,
            events: self.event_state(),
        })
    }

    /// `fmi2SetFMUstate`: a state of this model (same parameters) only. The phase stays (FMI 2.0:
    /// setting a state is no transition; in the instantiated state the master still initialises).
    pub fn set_state(&mut self, state: &FmuState) -> Status {
        let function = self.call(self.api.state_call("Set"));
        if let Err(status) = self.check_phase(&function, LIVE_PHASES) {
            return status;
        }
        if let Err(status) = self.ensure_sim() {
            return status;
        }
        if state.events.is_some() != self.events.is_some() {
            let (state_api, own) = match state.events {
                Some(_) => ("3.0", "2.0"),
                None => ("2.0", "3.0"),
            };
            return self.error(&format!(
                "{function}: a state of the FMI {state_api} FMU, not of this FMI {own} one"
            ));
        }
        let sim = self.sim.as_mut().expect("built above");
        if let Err(e) = sim.restore(&state.snapshot) {
            return self.error(&format!("{function}: {e}"));
        }
        self.set_event_state(state.events.as_ref());
        let tau = VARIABLES.iter().position(|v| v.role == Role::Tau).expect("tau");
        self.values[tau] = state.tau;
        self.impact = state.impact;
        self.last_internal_step = state.last_internal_step;
        self.start_time = state.start_time;
        self.invalidate();
        Status::Ok
    }
}
