//! The energy balance of a run and its watchdog: the energy error of every record against the
//! energy the run has available. Every number it compares or takes the largest of is finite: a
//! record or an energy error with a NaN or an infinity stops the run ([`EnergyAudit::push`]),
//! whatever `output.energy_watchdog` says.

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

    /// Takes the next record; returns its energy error judged with the scale so far, a finite
    /// number. A record with a NaN or an infinity ([`StepRecord::check_finite`]), or whose energy
    /// error or scale overflows, is refused with [`Error::NonFinite`] and leaves the audit as it
    /// was: the largest values here (`f64::max` drops a NaN) and the watchdog's comparison
    /// (`error > limit` is false for NaN) see finite numbers only.
    pub fn push(&mut self, r: &StepRecord) -> Result<f64, Error> {
        r.check_finite()?;
        let first = self.first.as_ref().unwrap_or(r);
        let largest_work = self.largest_work.max(r.torque_work.abs());
        let scale = self.floor.max(first.kinetic.abs() + self.potential + largest_work);
        let defect = (r.total - first.total - r.torque_work).abs();
        let overflow = [("energy scale", scale), ("energy error", defect / scale)]
            .into_iter()
            .find(|(_, v)| !v.is_finite());
        if let Some((quantity, value)) = overflow {
            return Err(Error::NonFinite {
                step: r.step,
                t: r.time,
                quantity,
                value,
            });
        }
        self.first.get_or_insert_with(|| r.clone());
        (self.largest_work, self.scale) = (largest_work, scale);
        self.largest_defect = self.largest_defect.max(defect);
        Ok(defect / scale)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A record of a swing at step `step`: total energy `total`, no torque.
    fn record(step: usize, total: f64) -> StepRecord {
        StepRecord {
            step,
            time: step as f64 / 100.0,
            kinetic: 0.5,
            gravity: total - 0.5,
            total,
            ..Default::default()
        }
    }

    #[test]
    fn a_nan_energy_is_refused_naming_step_time_and_quantity_and_leaves_the_audit_as_it_was() {
        let mut audit = EnergyAudit::new(1e-3, 2.0);
        assert_eq!(audit.push(&record(0, -1.0)).unwrap(), 0.0);
        assert_eq!(audit.push(&record(1, -1.25)).unwrap(), 0.25 / 2.5);
        let (error, scale) = (audit.error(), audit.scale());
        for (quantity, value) in [("total energy", f64::NAN), ("torque's work", f64::INFINITY)] {
            let mut r = record(41, -1.0);
            match quantity {
                "total energy" => r.total = value,
                _ => r.torque_work = value,
            }
            match audit.push(&r) {
                Err(Error::NonFinite {
                    step: 41,
                    t,
                    quantity: q,
                    ..
                }) if t == 0.41 && q == quantity => {}
                other => panic!("{quantity} = {value}: {other:?}"),
            }
            // the largest error is a number and the one before: f64::max would have dropped the NaN
            assert_eq!((audit.error(), audit.scale()), (error, scale), "{quantity}");
        }
    }

    #[test]
    fn an_energy_error_that_overflows_is_refused_though_every_energy_is_finite() {
        let mut audit = EnergyAudit::new(1e-3, 2.0);
        audit.push(&record(0, -f64::MAX)).unwrap();
        // ΔE = MAX − (−MAX) overflows
        let message = audit.push(&record(1, f64::MAX)).unwrap_err().to_string();
        assert!(
            message.starts_with("step 1 (t = 0.010000 s): the energy error is inf"),
            "{message}"
        );
        assert_eq!(audit.error(), 0.0, "the refused record is not in the audit");
    }

    #[test]
    fn a_record_refused_first_is_not_the_reference_of_the_next() {
        let mut audit = EnergyAudit::new(1e-3, 2.0);
        audit.push(&record(0, f64::NAN)).unwrap_err();
        // the first record taken is the reference: no error against itself
        assert_eq!(audit.push(&record(1, -1.0)).unwrap(), 0.0);
    }
}
