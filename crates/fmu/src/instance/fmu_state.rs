//! FMU states: what `fmi2GetFMUstate` saves of an instance ([`FmuState`]), its serialisation under
//! one checksum, and getting and setting an instance's state.

use pendulum_fem_core::{Error, Snapshot};

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

impl Instance {
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
}
