//! Newton's method with a backtracking line search for `min Φ(u)` subject to the hinge `C u = 0`.
//!
//! Iteration `k` at a feasible `u_k` with gradient `g` and Hessian `K` of `Φ` solves the
//! saddle-point system of [`crate::linsolve`] for the update `Δu` and the new multipliers `λ`.
//! The squared energy norm of the update (the Newton decrement),
//!
//! ```text
//! δ² = Δuᵀ K Δu = −Δuᵀ (g + Cᵀλ)   [J],
//! ```
//!
//! is NGSolve's `NewtonMinimization` error measure; the iteration stops when `δ² < tolerance` and the
//! full step is taken, exactly as there. A step is accepted when `Φ(u + sΔu) ≤ Φ(u) − 10⁻⁴ s δ²`
//! (Armijo) or when the change of `Φ` is below its rounding level; otherwise `s` is halved.
//! `Φ = +∞` (an inverted element) always backtracks.
//!
//! Because `C` is constant and the start is feasible, every iterate stays feasible: `C Δu = 0`.
//! Iterations are counted as linear solves; factorisations are reported separately (NGSolve factorises
//! once per iteration).
//!
//! **Files**: `settings` (what a solve is asked and reports), `evaluate` (the terms at a point and
//! the residual measures), `factor` (the factorisation and its state), `saddle` (the linear solve
//! of an iteration), `krylov` (the GMRES correction), `minimize` ([`Solver::minimize`]), `solve`
//! ([`Solver::solve`]); here the solver's workspace and the thresholds of its iterations.

use std::sync::Arc;

use crate::assembly::{Dirichlet, Pattern};
use crate::constraint::Hinge;
use crate::error::Error;
use crate::linsolve::Cholesky;

mod evaluate;
mod factor;
mod krylov;
mod minimize;
mod saddle;
mod settings;
mod solve;

pub use factor::FactorState;
pub use settings::{NewtonReport, NewtonSettings, Timings};

/// Workspace of the constrained Newton solver: the pattern, the factorisation and buffers, all
/// allocated once.
pub struct Solver {
    /// The sparse Cholesky factorisation (its symbolic analysis); `None` for a solver made by
    /// [`Solver::deferred`] until its first factorisation.
    chol: Option<Cholesky>,
    rows: [Vec<f64>; 2],
    /// The unknowns where either hinge row is not zero (the hinge edge's nodes), ascending: a
    /// product with a row sums over these alone ([`Solver::row_dot`]).
    row_support: Vec<usize>,
    g: Vec<f64>,
    k: Vec<f64>,
    rhs: Vec<f64>,
    trial: Vec<f64>,
    /// `K_f⁻¹ Cᵀ` (two columns) of the current factorisation, in its frame.
    hinge_columns: Vec<f64>,
    /// `(proxy angle, matrix key)` of the current factorisation.
    factor_frame: Option<(f64, f64)>,
    /// The matrix of the current factorisation, kept so that it can be remade exactly
    /// ([`Solver::factor_state`], [`Solver::restore_factor`]); a new `Arc` per factorisation.
    factored: Option<Arc<FactorState>>,
    /// Positions of the diagonal entries in the pattern's values.
    diagonal: Vec<usize>,
    /// Largest diagonal entry of the last factorised matrix \[N/m\].
    diagonal_max: f64,
    /// Degrees of freedom held at zero, imposed after every assembly.
    fixed: Dirichlet,
    /// The leading degrees of freedom (the pendulum's nodes) that turn with the proxy angle when a
    /// factorisation is reused in another frame; the others (a wall) stay as they are.
    rotating: usize,
    /// Accumulated timings.
    pub timings: Timings,
}

/// Multiple of the machine epsilon in the rounding floor of the residual check.
pub const ROUNDING_FACTOR: f64 = 10.0;

/// A residual that has stopped contracting is at the rounding of the forces in play when it is
/// below this fraction of them: the largest nodal sum of the magnitudes of every term's force
/// (elastic, inertia, gravity, torque, contact) and of the hinge reaction
/// (`Solver::forces_in_play`). The internal forces of a stiff body are differences of terms of
/// size `K |x|` and its stresses differences of strains near zero, so their rounding is far above
/// `ε` of the force itself; the stagnation levels of `tests/robustness.rs`' cases reach 1e-9 of the
/// forces in play, while an unconverged step leaves a residual of order 1e-3 or more of
/// them.
pub const FORCE_ROUNDING: f64 = 1e-8;

/// An energy balance that has stopped improving under a fresh tangent is accepted up to this
/// multiple of its bound (the rounding of `½ Δu·r` for a step that moves far); beyond it the
/// iteration goes on, and a step that cannot meet it is cut back: with the default
/// `solver.energy_tolerance` of 1e-12 a run of 2000 such steps keeps its balance within 2e-7.
pub const STALLED_ENERGY: f64 = 100.0;

/// A reused factorisation must reduce the residual at least by this factor per iteration.
pub const REFACTOR_CONTRACTION: f64 = 0.5;

/// An iteration of [`Solver::solve`] that contracts the residual by less than this factor makes
/// the rest of the solve correct each update with GMRES on the system's own Jacobian
/// ([`Solver::solve`]). A step whose iterations contract faster (the tutorial's swing: one or two
/// iterations, contractions of 1e-3 and below) never pays for it.
pub const SLOW_CONTRACTION: f64 = 0.02;

/// The largest Krylov space of the GMRES correction.
pub const KRYLOV_DIMENSION: usize = 4;

/// GMRES stops when it has reduced the Newton equation's residual by this factor; the correction
/// is not made when the symmetric update already meets it.
pub const KRYLOV_TOLERANCE: f64 = 1e-3;

/// The difference step of the Jacobian's products, relative to the length scale plus the largest
/// displacement, over the direction's largest entry: about the square root of the rounding of
/// the gradient.
pub const DIFFERENCE_STEP: f64 = 1e-8;

/// [`Solver::solve`] renews a reused factorisation when, at its last contraction, it would need
/// more than this many further iterations to meet the convergence criteria.
pub const REUSE_HORIZON: f64 = 5.0;

/// Full Newton steps that [`Solver::solve`] may take in a row although neither the residual nor
/// the natural monotonicity test says they improved (the watchdog of Chamberlain, Powell,
/// Lemaréchal and Pedersen, 1982). A penalty contact's force is zero on one side of the wall and
/// steep on the other: at a point just apart the tangent sees no contact, the full step drives
/// it into the wall (a soft head: 1e4 N of residual against 10 N before), and a line search
/// that insists on a smaller residual cut such steps to 1/16–1/32 for some 30 iterations (seed
/// 18's case 5 of `tests/robustness.rs`). Taken whole, with the tangent renewed at the new
/// iterate, the step's penetrating points are seen by the next tangent, which pulls them back:
/// that case's first impact converges in 5–15 iterations per sub-step. When the budget is spent
/// and the residual is still above the best iterate's, the solve returns to that iterate and
/// goes on with the damped search alone.
pub const WATCHDOG_STEPS: usize = 4;

impl Solver {
    /// Symbolic analysis of `pattern` and buffers for the hinge `hinge`.
    pub fn new(pattern: &Pattern, hinge: &Hinge) -> Result<Self, Error> {
        Self::with_bodies(pattern, hinge, Dirichlet::default(), pattern.n)
    }

    /// As [`Solver::new`] for a model of several bodies: `fixed` degrees of freedom held at zero,
    /// and the first `rotating` degrees of freedom those of the body whose frame the reused
    /// factorisation follows (see [`Solver::minimize`]).
    pub fn with_bodies(pattern: &Pattern, hinge: &Hinge, fixed: Dirichlet, rotating: usize) -> Result<Self, Error> {
        let mut solver = Self::deferred(pattern, hinge, fixed, rotating);
        solver.chol = Some(Cholesky::new(pattern)?);
        Ok(solver)
    }

    /// As [`Solver::with_bodies`] with the symbolic analysis put off to the first factorisation:
    /// for a model that may never factorise its full tangent (a reduced body steps in its own
    /// coordinates), whose set-up then does not pay for the fill-reducing ordering.
    pub fn deferred(pattern: &Pattern, hinge: &Hinge, fixed: Dirichlet, rotating: usize) -> Self {
        let n = pattern.n;
        let rows = hinge.dense_rows(n);
        Self {
            row_support: (0..n).filter(|&i| rows[0][i] != 0.0 || rows[1][i] != 0.0).collect(),
            rows,
            g: vec![0.0; n],
            k: vec![0.0; pattern.nnz()],
            rhs: vec![0.0; 3 * n],
            trial: vec![0.0; n],
            hinge_columns: vec![0.0; 2 * n],
            factor_frame: None,
            factored: None,
            diagonal: (0..n)
                .map(|i| pattern.position(i, i).expect("diagonal in pattern"))
                .collect(),
            diagonal_max: 0.0,
            fixed,
            rotating,
            chol: None,
            timings: Timings::default(),
        }
    }

    /// Stored entries of the Cholesky factor (0 before the symbolic analysis of a
    /// [`Solver::deferred`] solver).
    pub fn factor_nnz(&self) -> usize {
        self.chol.as_ref().map_or(0, Cholesky::factor_nnz)
    }

    /// The Cholesky factorisation `chol` of `pattern` (a solver's field), its symbolic analysis
    /// made now if it was put off ([`Solver::deferred`]).
    fn analysed<'a>(chol: &'a mut Option<Cholesky>, pattern: &Pattern) -> Result<&'a mut Cholesky, Error> {
        if chol.is_none() {
            *chol = Some(Cholesky::new(pattern)?);
        }
        Ok(chol.as_mut().expect("made above"))
    }

    /// The gradient `∇Φ` of the last assembly (a view for diagnostics).
    pub fn gradient(&self) -> &[f64] {
        &self.g
    }
}
