//! What a solve is asked and what it reports: [`NewtonSettings`], [`NewtonReport`] and the
//! accumulated [`Timings`] of the parts of an iteration.

#[cfg(doc)]
use super::Solver;

/// Newton settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSettings {
    /// Convergence threshold on `δ²` \[J\].
    pub tolerance: f64,
    /// Iterations allowed.
    pub max_iterations: usize,
    /// The residual at the accepted solution must satisfy `‖∇Φ + Cᵀλ‖∞ ≤ residual_tolerance · load_scale`.
    pub residual_tolerance: f64,
    /// Size of the applied nodal forces (gravity, inertia, torque) \[N\]; see [`NewtonSettings::residual_tolerance`].
    pub load_scale: f64,
    /// Largest distance of a node from the pivot \[m\], for the rounding floor of the residual check.
    pub length_scale: f64,
    /// Proxy angle of the starting point \[rad\]: the frame in which a reused factorisation is rotated.
    pub frame_angle: f64,
    /// Identifies the matrix family (the mass factor `1/(βΔt²)`); a change forces a refactorisation.
    pub matrix_key: f64,
    /// Allow reusing a factorisation from an earlier call (see [`Solver::minimize`]).
    pub reuse: bool,
    /// Turn \[rad\] by which [`Solver::solve`] rotates the residual before the linear solve (and the
    /// multipliers back): the energy-momentum Jacobian is `≈ Q(−Δφ/2) K` in the stiff modes, the
    /// tangent `K` at the end of the step seen from the mid-step frame (see
    /// [`crate::scheme::energy_momentum`]), so `Δφ/2` there; 0 for [`Solver::minimize`].
    pub residual_turn: f64,
}

/// What happened in a converged solve.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NewtonReport {
    /// Iterations (linear solves).
    pub iterations: usize,
    /// Numeric factorisations (at most one per iteration).
    pub factorizations: usize,
    /// `δ²` of every iteration \[J\].
    pub decrements: Vec<f64>,
    /// Line-search step lengths `s` of every iteration.
    pub step_lengths: Vec<f64>,
    /// `‖∇Φ + Cᵀλ‖∞` at the accepted solution \[N\].
    pub residual: f64,
}

/// Time spent in the parts of a Newton iteration \[s\].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// Energy, gradient and Hessian assembly.
    pub assembly: f64,
    /// Numeric Cholesky factorisation.
    pub factorization: f64,
    /// Triangular solves and the Schur complement.
    pub solve: f64,
    /// Energy-only evaluations of the line search.
    pub line_search: f64,
    /// Evaluations without a tangent (energy and gradient at the start of a solve and at trial
    /// points of a reused factorisation, gradients for the residual checks).
    pub residual: f64,
}
