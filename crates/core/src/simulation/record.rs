//! The output records of a [`Simulation`](super::Simulation): a row of `results.csv`
//! ([`StepRecord`], with its contact columns [`ContactRecord`]) and the nodal fields of a written
//! frame ([`Frame`], [`FrameData`]).
//!
//! **No result is NaN or infinite.** Every quantity of a record is a finite number, or the record
//! is refused with [`Error::NonFinite`] naming its step, time and the first quantity that is not
//! ([`StepRecord::check_finite`]): the one rule, which the stepper applies to every state it
//! reaches ([`Simulation::step`](super::Simulation::step)) and the run driver to every record it
//! writes.

#[cfg(doc)]
use super::Model;
use crate::error::Error;
use crate::post::NodalStress;

/// One row of `results.csv`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepRecord {
    /// Step number (0: the initial state).
    pub step: usize,
    /// Time \[s\].
    pub time: f64,
    /// Proxy angle, unwrapped \[rad\].
    pub theta: f64,
    /// Best-fit angular velocity \[rad/s\].
    pub omega: f64,
    /// Best-fit angular acceleration \[rad/s²\].
    pub alpha: f64,
    /// Kinetic energy \[J\].
    pub kinetic: f64,
    /// Strain energy \[J\].
    pub strain: f64,
    /// Gravitational energy relative to the pivot height \[J\].
    pub gravity: f64,
    /// Total energy: kinetic + strain + gravity + contact (the last 0 without a wall) \[J\].
    pub total: f64,
    /// Force of the hinge on the body \[N\].
    pub hinge_force: [f64; 2],
    /// Largest von Mises stress \[Pa\].
    pub von_mises_max: f64,
    /// Newton iterations of the step (0 for the initial state).
    pub newton_iterations: usize,
    /// Actuator torque `M(t)` \[N m\] (see [`Model::applied_torque`]).
    pub torque: f64,
    /// Work done by the actuator since the start \[J\]; `total − total(0)` equals it up to the
    /// integrator's energy error.
    pub torque_work: f64,
    /// Angular momentum about the pivot, `∫ ρ t x × v dA` \[kg m²/s\].
    pub angular_momentum: f64,
    /// The contact with the wall, when the model has one.
    pub contact: Option<ContactRecord>,
}

impl StepRecord {
    /// Every quantity of the record with its name, in the order of the columns of `results.csv`:
    /// its results, not its step and time (the clock's, from steps of a finite length) nor its
    /// counts.
    pub fn quantities(&self) -> impl Iterator<Item = (&'static str, f64)> + '_ {
        let contact = self.contact.iter().flat_map(|c| {
            [
                (CONTACT_GAP, c.gap),
                ("contact force", c.force),
                ("contact energy", c.energy),
            ]
        });
        [
            ("proxy angle θ", self.theta),
            ("angular velocity ω", self.omega),
            ("angular acceleration α", self.alpha),
            ("kinetic energy", self.kinetic),
            ("strain energy", self.strain),
            ("gravitational energy", self.gravity),
            ("total energy", self.total),
            ("hinge force's x component", self.hinge_force[0]),
            ("hinge force's y component", self.hinge_force[1]),
            ("largest von Mises stress", self.von_mises_max),
            ("torque", self.torque),
            ("torque's work", self.torque_work),
            ("angular momentum", self.angular_momentum),
        ]
        .into_iter()
        .chain(contact)
    }

    /// The first quantity of the record (in the order of [`StepRecord::quantities`]) that is NaN
    /// or infinite, with its value; `None` when all are finite. The contact gap may be `+∞`: no
    /// point of the head's arc faces the deformable wall's face (a head that swung over the pivot
    /// and passes behind the block, [`ContactRecord::gap`]).
    pub fn first_non_finite(&self) -> Option<(&'static str, f64)> {
        self.quantities()
            .find(|&(name, v)| !(v.is_finite() || (name == CONTACT_GAP && v == f64::INFINITY)))
    }

    /// The record, checked: [`Error::NonFinite`] names its step, its time and the first quantity
    /// that is NaN or infinite (see the module doc).
    pub fn check_finite(&self) -> Result<(), Error> {
        match self.first_non_finite() {
            None => Ok(()),
            Some((quantity, value)) => Err(Error::NonFinite {
                step: self.step,
                t: self.time,
                quantity,
                value,
            }),
        }
    }
}

/// The name of the contact gap among a record's quantities.
const CONTACT_GAP: &str = "contact gap";

/// The contact columns of a [`StepRecord`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactRecord {
    /// Smallest signed distance from the head's arc to the wall face \[m\] (negative: penetration;
    /// `+∞` where no point of the arc faces the deformable wall's face).
    pub gap: f64,
    /// Normal force of the wall on the head \[N\].
    pub force: f64,
    /// Contact energy \[J\] (part of `total`).
    pub energy: f64,
    /// Impacts so far.
    pub impacts: usize,
}

/// The state of the pendulum at one written time, with everything the frame writers need.
/// All arrays are per mesh node (vertices and mid-edge nodes).
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    /// Step number (0 is the initial state).
    pub step: usize,
    /// Time \[s\].
    pub time: f64,
    /// Rigid-body proxy angle \[rad\] (unwrapped).
    pub theta: f64,
    /// Displacement \[m\].
    pub displacement: &'a [[f64; 2]],
    /// Velocity \[m/s\].
    pub velocity: &'a [[f64; 2]],
    /// Acceleration \[m/s²\].
    pub acceleration: &'a [[f64; 2]],
    /// Plane-stress von Mises stress \[Pa\].
    pub von_mises: &'a [f64],
    /// Cauchy stress `[σxx, σyy, σxy]` \[Pa\].
    pub cauchy: &'a [[f64; 3]],
}

/// Nodal fields of the current state, owned, for the frame writers.
#[derive(Clone, Debug, Default)]
pub struct FrameData {
    /// Step number.
    pub step: usize,
    /// Time \[s\].
    pub time: f64,
    /// Proxy angle \[rad\].
    pub theta: f64,
    /// Displacement per node.
    pub displacement: Vec<[f64; 2]>,
    /// Velocity per node.
    pub velocity: Vec<[f64; 2]>,
    /// Acceleration per node.
    pub acceleration: Vec<[f64; 2]>,
    /// Nodal stresses.
    pub stress: NodalStress,
}

impl FrameData {
    /// Borrowed view for the writers.
    pub fn as_frame(&self) -> Frame<'_> {
        Frame {
            step: self.step,
            time: self.time,
            theta: self.theta,
            displacement: &self.displacement,
            velocity: &self.velocity,
            acceleration: &self.acceleration,
            von_mises: &self.stress.von_mises,
            cauchy: &self.stress.cauchy,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record with a distinct finite value in every quantity, with the contact columns.
    fn record() -> StepRecord {
        StepRecord {
            step: 41,
            time: 0.41,
            theta: 1.0,
            omega: 2.0,
            alpha: 3.0,
            kinetic: 4.0,
            strain: 5.0,
            gravity: 6.0,
            total: 7.0,
            hinge_force: [8.0, 9.0],
            von_mises_max: 10.0,
            newton_iterations: 3,
            torque: 11.0,
            torque_work: 12.0,
            angular_momentum: 13.0,
            contact: Some(ContactRecord {
                gap: 14.0,
                force: 15.0,
                energy: 16.0,
                impacts: 2,
            }),
        }
    }

    #[test]
    fn each_quantity_that_is_nan_or_infinite_is_the_one_the_error_names_with_step_and_time() {
        let clean = record();
        assert_eq!(clean.first_non_finite(), None);
        clean.check_finite().unwrap();
        let names: Vec<_> = clean.quantities().map(|(name, _)| name).collect();
        assert_eq!(names.len(), 16, "13 quantities and the 3 of the contact: {names:?}");
        // the values are distinct: a value of the list finds its field
        for (name, value) in clean.quantities() {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                if name == CONTACT_GAP && bad == f64::INFINITY {
                    continue;
                }
                let mut r = clean.clone();
                let [hx, hy] = &mut r.hinge_force;
                let slot = [
                    &mut r.theta,
                    &mut r.omega,
                    &mut r.alpha,
                    &mut r.kinetic,
                    &mut r.strain,
                    &mut r.gravity,
                    &mut r.total,
                    hx,
                    hy,
                    &mut r.von_mises_max,
                    &mut r.torque,
                    &mut r.torque_work,
                    &mut r.angular_momentum,
                ]
                .into_iter()
                .chain(
                    r.contact
                        .iter_mut()
                        .flat_map(|c| [&mut c.gap, &mut c.force, &mut c.energy]),
                )
                .find(|v| **v == value)
                .expect("the value is a field's");
                *slot = bad;
                assert_eq!(r.first_non_finite().map(|(n, _)| n), Some(name), "{name} = {bad}");
                let message = r.check_finite().unwrap_err().to_string();
                let expected = format!("step 41 (t = 0.410000 s): the {name} is {bad}");
                assert!(message.starts_with(&expected), "{message}");
                assert!(message.contains("time.dt"), "says what to try: {message}");
            }
        }
    }

    #[test]
    fn a_contact_gap_of_plus_infinity_is_a_head_facing_no_face_and_passes_but_minus_infinity_does_not() {
        let mut r = record();
        r.contact.as_mut().unwrap().gap = f64::INFINITY;
        assert_eq!(r.first_non_finite(), None);
        r.contact.as_mut().unwrap().gap = f64::NEG_INFINITY;
        assert_eq!(r.first_non_finite().map(|(n, _)| n), Some(CONTACT_GAP));
    }
}
