//! The `[initial]` section: the rigid rotation the pendulum starts from, its acceleration and its
//! elastic state, with their rules.

use serde::{Deserialize, Serialize};

use super::ranges::{finite, within, Mistakes};

/// How the initial acceleration is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum InitialAcceleration {
    /// Rigid-body acceleration `α₀ e_z × r − ω₀² r`, `α₀` from the torque balance about the pivot.
    Rigid,
    /// Zero, exactly as the tutorial starts.
    Zero,
}

/// The elastic state of the initial configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum InitialElastic {
    /// In elastic equilibrium with gravity, torque and the inertial forces of the rigid start
    /// (requires `acceleration = "rigid"`; the default there).
    Equilibrium,
    /// Undeformed (the tutorial's start; the default with `acceleration = "zero"`).
    Undeformed,
}

/// Initial state: a rigid rotation about the pivot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Initial {
    /// Initial angle \[deg\], counter-clockwise from hanging straight down.
    pub angle_deg: f64,
    /// Initial angular velocity \[rad/s\].
    pub angular_velocity: f64,
    /// Initial acceleration field.
    pub acceleration: InitialAcceleration,
    /// Elastic state of the start; `None`: equilibrium with a rigid start, undeformed with a zero one.
    pub elastic: Option<InitialElastic>,
}

impl Default for Initial {
    fn default() -> Self {
        Self {
            angle_deg: 20.0,
            angular_velocity: 0.0,
            acceleration: InitialAcceleration::Rigid,
            elastic: None,
        }
    }
}

impl Initial {
    /// The elastic state with its default filled in.
    pub fn elastic_state(&self) -> InitialElastic {
        self.elastic.unwrap_or(match self.acceleration {
            InitialAcceleration::Rigid => InitialElastic::Equilibrium,
            InitialAcceleration::Zero => InitialElastic::Undeformed,
        })
    }

    /// The `[initial]` rules.
    pub(super) fn validate(&self, m: &mut Mistakes) {
        m.check(within("initial.angle_deg", self.angle_deg, -360.0, 360.0, "deg"));
        m.check(finite("initial.angular_velocity", self.angular_velocity));
        if self.elastic == Some(InitialElastic::Equilibrium) && self.acceleration == InitialAcceleration::Zero {
            m.push(
                "initial.elastic",
                "initial.elastic = \"equilibrium\" needs initial.acceleration = \"rigid\" (a tilted body with zero \
                 acceleration has no equilibrium); allowed with \"zero\": \"undeformed\"",
            );
        }
    }
}
