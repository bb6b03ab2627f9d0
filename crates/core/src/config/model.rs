//! The `[model]` section: the full finite-element body or the reduced one (a floating frame with
//! a few elastic modes, [`crate::reduced`]), with its rules.

use serde::{Deserialize, Serialize};

use super::ranges::Mistakes;
use super::{ContactMethod, Scheme, TorqueProfile};

/// Which body the pendulum is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    /// Every node a degree of freedom, hyperelastic (the tutorial's model).
    Full,
    /// The rotation about the pivot and `modes` elastic modes (small strains).
    Reduced,
}

/// The most normal modes a reduced body may have: the modal solver's backward-error check
/// (`pendulum_fem::modal`) fails from about the 55th mode of the tutorial mesh on, so the reduced
/// body allows what `pendulum-fem modes --n` allows.
pub const MAX_MODES: usize = 50;

/// `[model]`: which body, and the reduced body's modes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ModelConfig {
    /// `"full"` or `"reduced"`.
    pub kind: ModelKind,
    /// Fixed-frame normal modes of the reduced body (the static correction modes come on top).
    pub modes: usize,
    /// Patches of unit normal load on the head's arc as static modes of the reduced body (with a
    /// wall), half an arc edge apart around each point where the turning body first touches it.
    pub contact_modes: usize,
}

impl Default for ModelConfig {
    fn default() -> Self {
        Self {
            kind: ModelKind::Full,
            modes: 8,
            contact_modes: 8,
        }
    }
}

impl ModelConfig {
    /// The `[model]` rules, and what the reduced body does not model.
    pub(super) fn validate(&self, config: &super::Config, m: &mut Mistakes) {
        if !(1..=MAX_MODES).contains(&self.modes) {
            m.push(
                "model.modes",
                format!(
                    "model.modes = {}: allowed 1 to {MAX_MODES} (the fixed-frame normal modes; the modal solver's \
                     accuracy check fails beyond about 55)",
                    self.modes
                ),
            );
        }
        if self.contact_modes > 64 {
            m.push(
                "model.contact_modes",
                format!("model.contact_modes = {}: allowed 0 to 64", self.contact_modes),
            );
        }
        if self.kind == ModelKind::Full {
            return;
        }
        let unsupported = if config.time.scheme != Scheme::EnergyMomentum {
            Some("time.scheme other than \"energy-momentum\"; the reduced body steps with its own discrete gradient")
        } else if config.torque.profile != TorqueProfile::None && !config.torque.follower {
            Some("torque.follower = false; the reduced body's torque turns with it")
        } else if config.wall.is_present() && config.contact.method != ContactMethod::EnergyConsistent {
            Some("contact.method = \"penalty\"; allowed: \"energy-consistent\"")
        } else {
            None
        };
        if let Some(what) = unsupported {
            m.push("model.kind", format!("model.kind = \"reduced\" does not model {what}"));
        }
    }
}
