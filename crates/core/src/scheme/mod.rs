//! The time schemes of the full model, in one home: the energy-momentum scheme
//! ([`energy_momentum`], the default) and the Newmark family written as an incremental potential
//! ([`newmark`]: the trapezoidal rule and HHT-α). Each implements [`TimeScheme`]: one step of the
//! full model from a [`Start`] and a guess, solved by Newton ([`crate::newton`]), not yet taken.
//! The stepper ([`crate::simulation`]) makes the guess, takes the step and cuts it back on
//! failure; the schemes never see which kind of body asks (the reduced body integrates its own
//! coordinates, [`crate::reduced::step`]).

pub mod energy_momentum;
pub mod newmark;

pub use energy_momentum::EnergyMomentum;
pub use newmark::{Hht, Newmark};

use crate::config::{Config, Scheme};
use crate::error::NewtonError;
use crate::model::{Model, State};
use crate::newton::Solver;

/// Relative equilibrium tolerance of a converged step: `‖∇Φ + Cᵀλ‖∞ ≤ 10⁻⁴ × load scale`, where the
/// load scale is the largest nodal gravity or inertia force. Together with the energy-norm criterion
/// (`solver.tolerance`) it guards against a small update that hides an unbalanced state.
pub const RESIDUAL_TOLERANCE: f64 = 1e-4;

/// The largest predicted turn of one energy-momentum (sub)step \[rad\]: a quarter turn. The scheme
/// conserves at any step, but its step must turn the body by less than half a turn (the hub and
/// proxy angles are unwrapped step to step, and Newton's rotated tangent degrades long before).
pub const EM_MAX_TURN: f64 = std::f64::consts::FRAC_PI_2;

/// What a step of the full model starts from.
pub struct Start<'a> {
    /// The model.
    pub model: &'a Model,
    /// The state at the step's start.
    pub state: &'a State,
    /// The hinge multipliers at the start \[N\].
    pub lambda: [f64; 2],
    /// The unwrapped proxy angle at the start \[rad\].
    pub theta: f64,
    /// The torque held as an input, if any \[N m\].
    pub held_torque: Option<f64>,
    /// The largest nodal force at the step's end time \[N\]: the scale of its residual check.
    pub load_scale: f64,
    /// The kinetic energy at the start \[J\].
    pub kinetic: f64,
    /// The elastic terms' start data of `state`, one per body ([`TimeScheme::uses_elastic_starts`];
    /// empty for a scheme that does not).
    pub elastic: &'a [Vec<f64>],
}

/// A step solved and not yet taken.
pub struct Stepped {
    /// The state at the step's end.
    pub state: State,
    /// The hinge multipliers of the step \[N\].
    pub lambda: [f64; 2],
    /// Newton iterations.
    pub iterations: usize,
    /// Numeric factorisations.
    pub factorizations: usize,
}

/// How Newton may iterate in a step.
#[derive(Clone, Copy, Debug)]
pub struct Iterate {
    /// Whether slow iterations may be corrected by GMRES ([`Solver::solve`]).
    pub correct: bool,
    /// Whether the tangent is made afresh instead of reusing the last factorisation.
    pub fresh_tangent: bool,
}

/// One time scheme of the full model (see the module doc).
pub trait TimeScheme: Send + Sync + std::fmt::Debug {
    /// Solves the step of length `dt` from `start`, Newton from `guess`.
    fn step(
        &self,
        start: &Start,
        dt: f64,
        guess: Vec<f64>,
        solver: &mut Solver,
        iterate: Iterate,
    ) -> Result<Stepped, NewtonError>;

    /// The rigid turn of a step over which the body turns by `phi = Δt ω̄` at its mean rate `ω̄`
    /// \[rad\]: `phi` itself, but for a scheme that advances rotations along chords.
    fn turn(&self, phi: f64) -> f64 {
        phi
    }

    /// Whether its steps start from the elastic terms' start data ([`Start::elastic`]); the strain
    /// energy of a state is then the sum of that data.
    fn uses_elastic_starts(&self) -> bool;

    /// Whether the state's `a` is the step's mean acceleration (the end-of-step value is then
    /// solved from the equation of motion when asked) rather than the end-of-step acceleration.
    fn keeps_mean_acceleration(&self) -> bool;

    /// Whether a step that fails where no halving is left is tried once more without the GMRES
    /// correction ([`Solver::solve`]; a scheme that minimises never corrects).
    fn retries_uncorrected(&self) -> bool;

    /// Whether its guess carries the shape's change over the last step on
    /// (see `Simulation`'s rotational guess).
    fn extrapolates_shape(&self) -> bool;
}

/// The time scheme of `config` (`time.scheme`).
pub fn for_config(config: &Config) -> Box<dyn TimeScheme> {
    match config.time.scheme {
        Scheme::EnergyMomentum => Box::new(EnergyMomentum {
            dissipation: config.time.dissipation,
        }),
        Scheme::Trapezoidal => Box::new(Hht::new(0.0)),
        Scheme::Hht => Box::new(Hht::new(config.time.hht_alpha)),
    }
}

/// The largest predicted turn of one (sub)step for the scheme of `config` \[rad\]: a quarter turn
/// for the energy-momentum scheme ([`EM_MAX_TURN`]), `time.max_rotation_deg` for the Newmark
/// schemes, which lose about `Δφ²/12` of the angular rate per step along a chord. The reduced
/// body's steps are split by the same rule.
pub fn largest_turn(config: &Config) -> f64 {
    match config.time.scheme {
        Scheme::EnergyMomentum => EM_MAX_TURN,
        Scheme::Trapezoidal | Scheme::Hht => config.time.max_rotation_deg.to_radians(),
    }
}
