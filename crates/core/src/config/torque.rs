//! The `[torque]` section: the profile of the actuator torque at the pivot, with its rules.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

use super::ranges::{finite, non_negative, range, Mistakes};

/// Time profile of the actuator torque.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TorqueProfile {
    /// No torque.
    None,
    /// `M = amplitude` for all times.
    Constant,
    /// `M = amplitude` from `start` on, 0 before.
    Step,
    /// Linear rise from 0 at `start` to `amplitude` at `start + duration`, constant after.
    Ramp,
    /// `M = amplitude sin(2π frequency (t − start) + phase)` from `start` on.
    Sine,
    /// Linear interpolation in a CSV table `time_s,torque_Nm`.
    Table,
}

impl TorqueProfile {
    /// The name in the configuration.
    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Constant => "constant",
            Self::Step => "step",
            Self::Ramp => "ramp",
            Self::Sine => "sine",
            Self::Table => "table",
        }
    }
}

/// Actuator torque at the pivot: the one description of the torque profile, which the torque
/// term ([`crate::terms::Torque`]) keeps and evaluates ([`crate::terms::Torque::value`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Torque {
    /// Time profile.
    pub profile: TorqueProfile,
    /// Amplitude \[N·m\], counter-clockwise positive.
    pub amplitude: f64,
    /// Start time \[s\].
    pub start: f64,
    /// Rise time of the ramp \[s\].
    pub duration: f64,
    /// Frequency of the sine \[Hz\].
    pub frequency: f64,
    /// Phase of the sine \[rad\].
    pub phase: f64,
    /// CSV table for `profile = "table"`.
    pub file: Option<PathBuf>,
    /// `true`: the load turns with the body (pure torque at every angle); `false`: fixed direction.
    pub follower: bool,
}

impl Default for Torque {
    fn default() -> Self {
        Self {
            profile: TorqueProfile::None,
            amplitude: 0.0,
            start: 0.0,
            duration: 0.0,
            frequency: 0.0,
            phase: 0.0,
            file: None,
            follower: true,
        }
    }
}

impl Torque {
    /// The `[torque]` rules: the keys each profile needs.
    pub(super) fn validate(&self, m: &mut Mistakes) {
        let t = self;
        m.check(finite("torque.amplitude", t.amplitude));
        m.check(non_negative("torque.start", t.start, "s"));
        let duration = m.check(non_negative("torque.duration", t.duration, "s"));
        let frequency = m.check(non_negative("torque.frequency", t.frequency, "Hz"));
        m.check(finite("torque.phase", t.phase));
        if duration && t.profile == TorqueProfile::Ramp && t.duration <= 0.0 {
            m.keep(range(
                "torque.duration",
                t.duration,
                "duration > 0 s for profile = \"ramp\"",
            ));
        }
        if frequency && t.profile == TorqueProfile::Sine && t.frequency <= 0.0 {
            m.keep(range(
                "torque.frequency",
                t.frequency,
                "frequency > 0 Hz for profile = \"sine\"",
            ));
        }
        if t.profile == TorqueProfile::Table && t.file.is_none() {
            m.push(
                "torque.file",
                "torque.file: required for profile = \"table\" (a CSV time_s,torque_Nm)",
            );
        }
    }
}

impl super::Config {
    /// This configuration with a torque input declared: `[torque] profile = "constant"`,
    /// `amplitude = 0`, so that the model has a torque term whose value an input holds
    /// ([`Simulation::set_torque`](crate::simulation::Simulation::set_torque)). The one declaration for the
    /// FMU's `tau` and the Python package's.
    pub fn with_torque_input(&self) -> Self {
        let mut c = self.clone();
        c.torque.profile = TorqueProfile::Constant;
        c.torque.amplitude = 0.0;
        c
    }
}
