//! The stepper: a [`Simulation`] owns the model ([`Model`], the full finite-element operators) and
//! one body of either kind behind one interface (`dynamics`: the full body, every node's
//! displacement; or the reduced body, a floating frame and a few modes), and advances it step by
//! step. Nothing outside `dynamics` asks which kind it has.
//!
//! **Initial state** (pivot at the origin, `R = R(θ₀)`): `u₀ = (R − I) X`, `v₀ = ω₀ e_z × x`,
//! `x = R X`. The initial acceleration is either zero (the tutorial's start) or the rigid-body value
//! `a₀ = α₀ e_z × x − ω₀² x`, with `α₀ = (τ_g + M(0)) / I_pivot` from the torque balance about the
//! pivot: `τ_g = −ρ t g ∫ x_x dA` is the moment of gravity and `I_pivot = ρ t ∫ |X|² dA`.
//!
//! With the rigid start the full body is also put into elastic equilibrium with gravity, the
//! torque and the d'Alembert forces of that rigid motion: `u₀` minimises
//! `Π_el(u) + Π_g(u) + Π_torque(u, 0) + (M a₀)·u` under the hinge, starting from the rigid rotation.
//! The rotation about the pivot is a zero-energy mode of that static problem (its moment balance
//! is what fixes `α₀`), so a mass term `½ (u − u_rigid)ᵀ M (u − u_rigid) / (0.01 s)²` pins it (the
//! conditioning of an ordinary step); its residual force is removed by re-centring it on the
//! solution and solving again (proximal point iterations, a few passes). Starting undeformed
//! instead excites axial vibrations that the trapezoidal rule never damps. The `"zero"` start is
//! the tutorial's: undeformed, at rest in its own frame (`initial.elastic = "undeformed"` also gives
//! an undeformed rigid start, for comparisons with codes that start that way).
//!
//! **A step in named levels** (`levels`, `impact`): an *output step* of length `Δt`
//! ([`Simulation::step`]) is resolved into impacts (`impact`: the touch located, the impact in
//! sub-steps of its own time scale) or split into equal *sub-steps* by the predicted rotation;
//! each sub-step is an *attempt* of the body's step (the full body: a time scheme of
//! [`crate::scheme`] solved by Newton; the reduced body: its own step in its coordinates), halved
//! on failure as `solver.max_cutbacks` allows ([`crate::config::Cutbacks`]); then the run stops
//! with an error naming the step, the time and the last residual ([`Error::TimeStep`]).
//!
//! **Files**: `dynamics` (the body interface) with `full` and `reduced` (its two kinds), `levels`
//! (output step, sub-step, attempt), `impact` (impact resolution and contact events), `stepper`
//! (the public stepping interface and outputs on request), `measures` (records, frames, the
//! rigid-body rates), `init` (set-up and initial state), `snapshot`, `record`, `clock`, `pool`,
//! `split` (a co-simulation master's step as internal steps).

#[cfg(doc)]
use crate::error::Error;
use crate::linsolve::Cholesky;
use crate::model::State;
use crate::rigid::Unwrap;

mod clock;
mod dynamics;
mod events;
mod full;
mod impact;
mod init;
mod interface;
mod levels;
mod measures;
mod pool;
mod record;
mod reduced;
pub(crate) mod snapshot;
pub mod split;
mod stepper;

pub use crate::model::{
    fingerprint, forget_shared, Body, BodySpec, Fingerprint, Model, CONTACT_BOUNDARY, HINGE_BOUNDARY,
};
pub use crate::scheme::RESIDUAL_TOLERANCE;
pub use events::{ContactEvent, ContactEventKind};
pub use init::Built;
pub use record::{ContactRecord, Frame, FrameData, StepRecord};
pub use snapshot::{Snapshot, SNAPSHOT_VERSION};
pub use stepper::Energies;

use clock::Clock;
use dynamics::Dynamics;
use impact::Impacts;
use measures::Kinematics;

/// A running simulation.
pub struct Simulation {
    /// The model (the full finite-element operators).
    pub model: Model,
    /// The body, full or reduced.
    body: Dynamics,
    /// The current state as both kinds of body present it.
    now: Now,
    /// Impacts: the events so far and the impact in progress.
    contact: Impacts,
    /// Steps done.
    pub step: usize,
    /// Newton iterations (linear solves) so far.
    pub total_iterations: usize,
    /// Numeric factorisations of the full tangent so far.
    pub total_factorizations: usize,
    /// Cut-backs (halved attempts) so far.
    pub cutbacks: usize,
    /// The time of the state as `base + count · dt` over a run of equal steps.
    clock: Clock,
    /// Newton iterations of the last step (0 before the first).
    last_iterations: usize,
    /// Nodal stress evaluations so far ([`Simulation::stress_evaluations`]).
    stress_evaluations: usize,
    /// Contact events copied by snapshots and restores ([`Simulation::events_copied`]).
    events_copied: std::sync::atomic::AtomicUsize,
    /// For [`Simulation::acceleration_field`]: the mass matrix factorised, the hinge rows and
    /// `M⁻¹Cᵀ`, made on first use.
    mass_solver: Option<(Cholesky, [Vec<f64>; 2], Vec<f64>)>,
}

/// The current state as both kinds of body present it: the full model's fields (for a reduced
/// body, those its contact reads after every step: the head's arc and the block; the rest is
/// rebuilt from its coordinates when read, [`Simulation::displacement`]), the hinge multipliers,
/// the proxy angle and what the terms read of the step's start.
pub(crate) struct Now {
    /// The fields and the time.
    pub state: State,
    /// The hinge multipliers \[N\].
    pub lambda: [f64; 2],
    /// Proxy angle, unwrapped \[rad\].
    pub theta: f64,
    /// The unwrapping of θ.
    pub unwrap: Unwrap,
    /// The torque held by [`Simulation::set_torque`] \[N m\], if any.
    pub held_torque: Option<f64>,
    /// Work of the torque since the start \[J\].
    pub torque_work: f64,
    /// Rigid-body measures of the current state, once computed.
    pub rates: Option<Kinematics>,
    /// `[strain, gravity, contact]` energy of the current state \[J\], once computed (a step
    /// checks them, the record then reads them).
    pub energies: Option<[f64; 3]>,
}

impl Now {
    /// Forgets what was computed of the state (it changed): its rates and energies.
    pub fn forget_measures(&mut self) {
        self.rates = None;
        self.energies = None;
    }

    /// The [`crate::terms::StepContext`] of the current state by itself.
    pub fn context(&self) -> crate::terms::StepContext<'_> {
        crate::terms::StepContext::at(&self.state.u, self.state.t, self.theta, self.held_torque)
    }
}
