//! The output records of a [`Simulation`](super::Simulation): a row of `results.csv`
//! ([`StepRecord`], with its contact columns [`ContactRecord`]) and the nodal fields of a written
//! frame ([`Frame`], [`FrameData`]).

#[cfg(doc)]
use super::Model;
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

/// The contact columns of a [`StepRecord`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactRecord {
    /// Smallest signed distance from the head's arc to the wall face \[m\] (negative: penetration).
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
