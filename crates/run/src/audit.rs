//! The energy balance of a run and its watchdog: the energy error of every record against the
//! energy the run has available.

use pendulum_fem_core::simulation::StepRecord;
use pendulum_fem_core::Error;

/// The energy balance of a run, fed one [`StepRecord`] at a time.
///
/// The **energy error** at step n is `|ΔE − W| / scale`, with `ΔE = E_total(tₙ) − E_total(0)` and
/// `W` the work of the torque up to tₙ (`torque_work_J`): without external work the total energy is
/// conserved, so whatever remains is the integrator's (or a divergence's) doing. The **energy
/// scale** is the energy the run has available: the initial kinetic energy, plus the weight times
/// the largest change of the centroid's height that the swing allows ([`Model::potential_range`]),
/// plus the largest |W| so far; never below the floor `10⁻³ m g₀ L` ([`Model::energy_floor`]), for
/// a body that has nothing to move it. The scale is known from the first step on (only the
/// torque's work can raise it), so the watchdog judges the first steps of a swing by what the
/// swing has available, not by the little kinetic energy it has gained so far.
///
/// [`Model::potential_range`]: pendulum_fem_core::simulation::Model::potential_range
/// [`Model::energy_floor`]: pendulum_fem_core::simulation::Model::energy_floor
#[derive(Clone, Debug)]
pub struct EnergyAudit {
    first: Option<StepRecord>,
    floor: f64,
    /// Weight times the centroid's possible height change \[J\].
    potential: f64,
    scale: f64,
    /// Largest `|W|` \[J\].
    largest_work: f64,
    /// Largest `|ΔE − W|` \[J\].
    largest_defect: f64,
}

impl EnergyAudit {
    /// An audit with the given floor of the energy scale and the weight times the centroid's
    /// possible height change ([`pendulum_fem_core::simulation::Model::potential_range`]) \[J\].
    pub fn new(floor: f64, potential: f64) -> Self {
        Self {
            first: None,
            floor,
            potential,
            scale: floor.max(potential),
            largest_work: 0.0,
            largest_defect: 0.0,
        }
    }

    /// The audit of a run of `model`.
    pub fn of(model: &pendulum_fem_core::simulation::Model) -> Self {
        Self::new(model.energy_floor(), model.potential_range())
    }

    /// Takes the next record; returns its energy error judged with the scale so far.
    pub fn push(&mut self, r: &StepRecord) -> f64 {
        let first = self.first.get_or_insert_with(|| r.clone());
        self.largest_work = self.largest_work.max(r.torque_work.abs());
        let available = first.kinetic.abs() + self.potential + self.largest_work;
        self.scale = self.floor.max(available);
        let defect = (r.total - first.total - r.torque_work).abs();
        self.largest_defect = self.largest_defect.max(defect);
        defect / self.scale
    }

    /// The floor of the energy scale \[J\].
    pub fn floor(&self) -> f64 {
        self.floor
    }

    /// The energy scale so far \[J\].
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The largest energy error so far, with the current scale.
    pub fn error(&self) -> f64 {
        self.largest_defect / self.scale
    }

    /// The watchdog's error for `r`: time, energies and what to try.
    pub fn divergence(&self, r: &StepRecord, limit: f64) -> Error {
        let first = self.first.as_ref().unwrap_or(r);
        let defect = r.total - first.total - r.torque_work;
        Error::Divergence {
            step: r.step,
            t: r.time,
            message: format!(
                "energy error {:.3e} of the energy scale {:.4e} J exceeds output.energy_watchdog = {limit}: \
                 the total energy changed by {:.4e} J while the torque did {:.4e} J of work (now kinetic {:.4e} J, \
                 strain {:.4e} J, gravity {:.4e} J). The step is probably too large for this motion: try a smaller \
                 time.dt or time.max_rotation_deg, or time.scheme = \"hht\"; output.energy_watchdog = 0 runs on \
                 regardless",
                defect.abs() / self.scale,
                self.scale,
                r.total - first.total,
                r.torque_work,
                r.kinetic,
                r.strain,
                r.gravity
            ),
        }
    }
}
