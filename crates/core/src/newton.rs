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

use std::sync::Arc;

use crate::assembly::{Dirichlet, Pattern};
use crate::constraint::Hinge;
use crate::error::NewtonError;
use crate::linsolve::Cholesky;
use crate::terms::{StepContext, Term};
use crate::Error;

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
    /// [`crate::energy_momentum`]), so `Δφ/2` there; 0 for [`Solver::minimize`].
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

/// The matrix of a factorisation and the frame it was made in: enough to remake it exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct FactorState {
    /// Upper-triangle values of the factorised matrix in the fixed pattern.
    pub values: Vec<f64>,
    /// `(proxy angle, matrix key)` of the factorisation (see [`NewtonSettings`]).
    pub frame: (f64, f64),
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

/// Workspace of the constrained Newton solver: the pattern, the factorisation and buffers, all
/// allocated once.
pub struct Solver {
    chol: Cholesky,
    rows: [Vec<f64>; 2],
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
/// `ε` of the force itself; measured stagnation levels reach 1e-9 of the forces in play (see
/// `tests/robustness.rs`), while an unconverged step leaves a residual of order 1e-3 or more of
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

/// The best iterate of a solve (the smallest residual) and where the watchdog stands.
struct Watchdog {
    u: Vec<f64>,
    lambda: [f64; 2],
    residual: f64,
    /// full steps taken since the best iterate without the line search's consent
    strikes: usize,
    /// false once the solve has returned to the best iterate
    armed: bool,
}

impl Watchdog {
    fn new(u: &[f64], lambda: [f64; 2], residual: f64) -> Self {
        Self {
            u: u.to_vec(),
            lambda,
            residual,
            strikes: 0,
            armed: WATCHDOG_STEPS > 0,
        }
    }

    /// Whether a full step that the line search refused may be taken (counted).
    fn allows(&mut self) -> bool {
        let allowed = self.armed && self.strikes < WATCHDOG_STEPS;
        self.strikes += usize::from(allowed);
        allowed
    }

    /// After an accepted iterate with residual `r`: whether the solve must return to the best
    /// iterate (the budget spent without a better one); otherwise the best is updated.
    fn must_return(&mut self, u: &[f64], lambda: [f64; 2], r: f64) -> bool {
        if r < self.residual {
            self.u.copy_from_slice(u);
            (self.lambda, self.residual, self.strikes) = (lambda, r, 0);
            return false;
        }
        if self.armed && self.strikes >= WATCHDOG_STEPS {
            self.armed = false;
            return true;
        }
        false
    }
}

/// `angle` wrapped into `[−π, π]` (the representative closest to 0, [`crate::post::unwrap_near`]).
pub fn wrap_angle(angle: f64) -> f64 {
    crate::post::unwrap_near(angle, 0.0)
}

/// Rotates every `(x, y)` pair of `v` by `angle`.
fn rotate_pairs(v: &mut [f64], angle: f64) {
    let (s, c) = angle.sin_cos();
    for p in v.chunks_exact_mut(2) {
        let (x, y) = (p[0], p[1]);
        p[0] = c * x - s * y;
        p[1] = s * x + c * y;
    }
}

fn residual_norm_of(g: &[f64], rows: &[Vec<f64>; 2], lam: [f64; 2]) -> f64 {
    (0..g.len())
        .map(|i| (g[i] + rows[0][i] * lam[0] + rows[1][i] * lam[1]).abs())
        .fold(0.0, f64::max)
}

/// Solves the small dense system `a x = b` by Gaussian elimination with partial pivoting; `None`
/// when it is singular.
fn solve_small(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let m = b.len();
    for c in 0..m {
        let p = (c..m).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() <= 1e-300 || !a[p][c].is_finite() {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..m {
            let f = a[r][c] / a[c][c];
            for k in c..m {
                a[r][k] -= f * a[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = vec![0.0; m];
    for r in (0..m).rev() {
        x[r] = (b[r] - (r + 1..m).map(|k| a[r][k] * x[k]).sum::<f64>()) / a[r][r];
    }
    Some(x)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Solver {
    /// Symbolic analysis of `pattern` and buffers for the hinge `hinge`.
    pub fn new(pattern: &Pattern, hinge: &Hinge) -> Result<Self, Error> {
        Self::with_bodies(pattern, hinge, Dirichlet::default(), pattern.n)
    }

    /// As [`Solver::new`] for a model of several bodies: `fixed` degrees of freedom held at zero,
    /// and the first `rotating` degrees of freedom those of the body whose frame the reused
    /// factorisation follows (see [`Solver::minimize`]).
    pub fn with_bodies(pattern: &Pattern, hinge: &Hinge, fixed: Dirichlet, rotating: usize) -> Result<Self, Error> {
        let n = pattern.n;
        let chol = Cholesky::new(pattern)?;
        Ok(Self {
            rows: hinge.dense_rows(n),
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
            chol,
            timings: Timings::default(),
        })
    }

    /// Stored entries of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.chol.factor_nnz()
    }

    fn energy(terms: &[&dyn Term], u: &[f64], cx: &StepContext) -> f64 {
        terms.iter().map(|term| term.energy(u, cx)).sum()
    }

    fn assemble(&mut self, pattern: &Pattern, terms: &[&dyn Term], u: &[f64], cx: &StepContext) -> f64 {
        let start = std::time::Instant::now();
        self.g.iter_mut().for_each(|x| *x = 0.0);
        self.k.iter_mut().for_each(|x| *x = 0.0);
        let mut phi = 0.0;
        for term in terms {
            phi += term.assemble(u, cx, pattern, &mut self.g, &mut self.k);
        }
        self.fixed.apply_vector(&mut self.g);
        self.fixed.apply_matrix(&mut self.k);
        self.timings.assembly += start.elapsed().as_secs_f64();
        phi
    }

    /// The Hessian alone at `u` into `self.k`, where `self.g` already holds the gradient at `u`
    /// (each term's `assemble` adds exactly its `add_hessian` and its `energy_gradient`, so the
    /// gradient is the one a full [`Solver::assemble`] would make, bit for bit).
    fn assemble_hessian(&mut self, pattern: &Pattern, terms: &[&dyn Term], u: &[f64], cx: &StepContext) {
        let start = std::time::Instant::now();
        self.k.iter_mut().for_each(|x| *x = 0.0);
        for term in terms {
            term.add_hessian(u, cx, pattern, &mut self.k);
        }
        self.fixed.apply_matrix(&mut self.k);
        self.timings.assembly += start.elapsed().as_secs_f64();
    }

    /// The residual a converged state must reach: `residual_tolerance × load_scale`, but never
    /// below the rounding level of the residual itself, `ROUNDING_FACTOR · ε · max diag K · length_scale`
    /// (internal forces are differences of terms of size `K |x|`; on fine meshes the nodal loads
    /// shrink like `h²` while that level does not).
    fn residual_bound(&self, settings: &NewtonSettings) -> f64 {
        let rounding = ROUNDING_FACTOR * f64::EPSILON * self.diagonal_max * settings.length_scale;
        (settings.residual_tolerance * settings.load_scale).max(rounding)
    }

    /// The forces in play at `u` with the multipliers `lambda`: the largest over the degrees of
    /// freedom of `Σ_terms |f_term| + |Cᵀλ|` \[N\], the level at which the residual's rounding
    /// sits ([`FORCE_ROUNDING`]). Leaves `self.g` untouched; costs one gradient pass per term, and
    /// is evaluated only when a step meets the energy criterion but not the residual bound.
    fn forces_in_play(&self, terms: &[&dyn Term], u: &[f64], cx: &StepContext, lambda: [f64; 2]) -> f64 {
        let n = self.g.len();
        let mut level: Vec<f64> = (0..n)
            .map(|i| (self.rows[0][i] * lambda[0] + self.rows[1][i] * lambda[1]).abs())
            .collect();
        let mut one = vec![0.0; n];
        for term in terms {
            one.iter_mut().for_each(|x| *x = 0.0);
            term.add_gradient(u, cx, &mut one);
            level.iter_mut().zip(&one).for_each(|(l, f)| *l += f.abs());
        }
        self.fixed.apply_vector(&mut level);
        level.into_iter().fold(0.0, f64::max)
    }

    /// Whether a residual `r` that did not contract below half of `r_prev` is at the rounding of
    /// the forces in play at `u` ([`FORCE_ROUNDING`]).
    fn stagnated_at_rounding(
        &self,
        terms: &[&dyn Term],
        u: &[f64],
        cx: &StepContext,
        lambda: [f64; 2],
        r: f64,
        r_prev: f64,
    ) -> bool {
        r > REFACTOR_CONTRACTION * r_prev && r <= FORCE_ROUNDING * self.forces_in_play(terms, u, cx, lambda)
    }

    /// Energy and gradient (no Hessian) at `u` into `self.g`.
    fn energy_gradient(&mut self, terms: &[&dyn Term], u: &[f64], cx: &StepContext) -> f64 {
        let start = std::time::Instant::now();
        self.g.iter_mut().for_each(|x| *x = 0.0);
        let mut phi = 0.0;
        for term in terms {
            phi += term.energy_gradient(u, cx, &mut self.g);
        }
        self.fixed.apply_vector(&mut self.g);
        self.timings.residual += start.elapsed().as_secs_f64();
        phi
    }

    /// Gradient only at `u` into `self.g`.
    fn gradient_only(&mut self, terms: &[&dyn Term], u: &[f64], cx: &StepContext) {
        let start = std::time::Instant::now();
        self.g.iter_mut().for_each(|x| *x = 0.0);
        for term in terms {
            term.add_gradient(u, cx, &mut self.g);
        }
        self.fixed.apply_vector(&mut self.g);
        self.timings.residual += start.elapsed().as_secs_f64();
    }

    /// Solves `K̃ Δu + Cᵀλ = −g`, `C(u + Δu) = 0` with the current factorisation, rotated by `dphi`
    /// from its frame into the current one; returns `(Δu, λ, δ²)`.
    /// Numeric factorisation of `self.k` in the frame of `settings`, and the hinge columns
    /// `K⁻¹ Cᵀ` in that frame; counted in `report`.
    fn factorize(
        &mut self,
        pattern: &Pattern,
        settings: &NewtonSettings,
        iteration: usize,
        report: &mut NewtonReport,
    ) -> Result<(), NewtonError> {
        let start = std::time::Instant::now();
        let factored = self.chol.factor(pattern, &self.k);
        self.timings.factorization += start.elapsed().as_secs_f64();
        report.factorizations += 1;
        if factored.is_err() {
            self.factor_frame = None;
            self.factored = None;
            return Err(NewtonError::SingularTangent { iteration });
        }
        let state = Arc::new(FactorState {
            values: self.k.clone(),
            frame: (settings.frame_angle, settings.matrix_key),
        });
        self.finish_factor(state);
        Ok(())
    }

    /// The hinge columns, frame and diagonal scale of the factorisation of `state` just made.
    fn finish_factor(&mut self, state: Arc<FactorState>) {
        let start = std::time::Instant::now();
        let n = self.g.len();
        self.hinge_columns[..n].copy_from_slice(&self.rows[0]);
        self.hinge_columns[n..].copy_from_slice(&self.rows[1]);
        self.chol.solve_in_place(&mut self.hinge_columns);
        self.timings.solve += start.elapsed().as_secs_f64();
        self.factor_frame = Some(state.frame);
        // the pendulum's: other bodies' rows (a wall at rest, unit rows of fixed nodes) add no rounding
        self.diagonal_max = self.diagonal[..self.rotating]
            .iter()
            .fold(0.0f64, |m, &k| m.max(state.values[k].abs()));
        self.factored = Some(state);
    }

    /// The matrix and frame of the current factorisation (`None` before the first one): what
    /// [`Solver::restore_factor`] needs to remake it. Cheap (a shared pointer).
    pub fn factor_state(&self) -> Option<Arc<FactorState>> {
        self.factored.clone()
    }

    /// Makes `state` the current factorisation again (`None`: none, the next solve factorises).
    /// The numeric factorisation of the same values with the same symbolic analysis is the same
    /// bit for bit (faer's factorisation is deterministic), so the solver continues exactly as it
    /// would have from `state`. Nothing is done when `state` is already the current one.
    pub fn restore_factor(&mut self, pattern: &Pattern, state: Option<Arc<FactorState>>) -> Result<(), Error> {
        let same = match (&self.factored, &state) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        if same {
            return Ok(());
        }
        let Some(state) = state else {
            self.factor_frame = None;
            self.factored = None;
            return Ok(());
        };
        if state.values.len() != pattern.nnz() {
            return Err(Error::Input(format!(
                "factorisation state: {} matrix values for a pattern of {} entries",
                state.values.len(),
                pattern.nnz()
            )));
        }
        let start = std::time::Instant::now();
        let factored = self.chol.factor(pattern, &state.values);
        self.timings.factorization += start.elapsed().as_secs_f64();
        if factored.is_err() {
            self.factor_frame = None;
            self.factored = None;
            return Err(Error::Input(
                "factorisation state: the saved matrix does not factorise".into(),
            ));
        }
        self.finish_factor(state);
        Ok(())
    }

    fn constrained_solve(&mut self, u: &[f64], dphi: f64, turn: f64) -> (Vec<f64>, [f64; 2], f64) {
        let start = std::time::Instant::now();
        let n = self.g.len();
        for i in 0..n {
            self.rhs[i] = -self.g[i];
        }
        let (du, lam) = self.saddle_solve(Some(u), dphi, turn);
        let decrement = -(dot(&du, &self.g) + lam[0] * dot(&self.rows[0], &du) + lam[1] * dot(&self.rows[1], &du));
        self.timings.solve += start.elapsed().as_secs_f64();
        (du, lam, decrement)
    }

    /// Solves the saddle-point system with the factorised matrix for the right-hand side in
    /// `self.rhs[..n]`: `K̃ x + Cᵀμ = rhs` with `C (u + x) = 0` (`C x = 0` without `u`), the
    /// matrix in its frame turned by `dphi` and the right-hand side by `turn`.
    fn saddle_solve(&mut self, u: Option<&[f64]>, dphi: f64, turn: f64) -> (Vec<f64>, [f64; 2]) {
        let n = self.g.len();
        // the right-hand side turned by `turn`, rotated by −dphi into the factor's frame, solved,
        // rotated back.
        let y = &mut self.rhs[..n];
        let rot = self.rotating;
        if turn - dphi != 0.0 {
            rotate_pairs(&mut y[..rot], turn - dphi);
        }
        self.chol.solve_in_place(y);
        if dphi != 0.0 {
            rotate_pairs(&mut y[..rot], dphi);
        }
        // The hinge columns K⁻¹Cᵀ in the current frame: Q(dphi) K_f⁻¹ Q(−dphi) Cᵀ. A rotation of
        // the two columns of Cᵀ (each node's weight times e_x, e_y) mixes them:
        // Q(β) c_x = cos β c_x + sin β c_y, Q(β) c_y = −sin β c_x + cos β c_y, β = −dphi.
        let (sb, cb) = (-dphi).sin_cos();
        let (fx, fy) = self.hinge_columns.split_at(n);
        let (zx, zy) = self.rhs[n..].split_at_mut(n);
        for i in 0..n {
            zx[i] = cb * fx[i] + sb * fy[i];
            zy[i] = -sb * fx[i] + cb * fy[i];
        }
        if dphi != 0.0 {
            rotate_pairs(&mut zx[..rot], dphi);
            rotate_pairs(&mut zy[..rot], dphi);
        }
        let (y, z) = self.rhs.split_at(n);
        let (zx, zy) = z.split_at(n);
        let s = [
            [dot(&self.rows[0], zx), dot(&self.rows[0], zy)],
            [dot(&self.rows[1], zx), dot(&self.rows[1], zy)],
        ];
        // C(u + Δu) = 0 with Δu = y − Zλ  ⇒  S λ = C y + C u.
        let b = match u {
            Some(u) => [
                dot(&self.rows[0], y) + dot(&self.rows[0], u),
                dot(&self.rows[1], y) + dot(&self.rows[1], u),
            ],
            None => [dot(&self.rows[0], y), dot(&self.rows[1], y)],
        };
        let det = s[0][0] * s[1][1] - s[0][1] * s[1][0];
        let lam = [
            (b[0] * s[1][1] - b[1] * s[0][1]) / det,
            (s[0][0] * b[1] - s[1][0] * b[0]) / det,
        ];
        let du: Vec<f64> = (0..n).map(|i| y[i] - zx[i] * lam[0] - zy[i] * lam[1]).collect();
        // the turned system carries the turned multipliers: Q(turn) Cᵀλ = Cᵀ R(turn) λ
        let lam = if turn != 0.0 {
            let (s, c) = (-turn).sin_cos();
            [c * lam[0] - s * lam[1], s * lam[0] + c * lam[1]]
        } else {
            lam
        };
        (du, lam)
    }

    /// Improves the update `(du, lam)` that the factorised symmetric matrix gave at `u` towards
    /// the solution of the Newton equation with the system's own Jacobian `J`,
    /// `g + J Δu + Cᵀλ = 0`, `C Δu = 0` (`self.g` holds `g` and is kept): GMRES on the correction,
    /// preconditioned by the same factorisation, `J` applied by differences of the gradient.
    /// Returns `None` when GMRES does not reduce the Newton equation's residual by half.
    // the system (terms, context), the point and its update, the factor's frames
    #[allow(clippy::too_many_arguments)]
    fn krylov_refine(
        &mut self,
        terms: &[&dyn Term],
        cx: &StepContext,
        u: &[f64],
        (du, lam, current): (&[f64], [f64; 2], [f64; 2]),
        (dphi, turn): (f64, f64),
        length_scale: f64,
    ) -> Option<(Vec<f64>, [f64; 2])> {
        let n = u.len();
        let g0 = self.g.clone();
        let reach = length_scale + u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let apply = |this: &mut Self, x: &[f64], mu: [f64; 2]| -> Option<Vec<f64>> {
            let size = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            if size == 0.0 {
                return Some(
                    (0..n)
                        .map(|i| mu[0] * this.rows[0][i] + mu[1] * this.rows[1][i])
                        .collect(),
                );
            }
            let h = DIFFERENCE_STEP * reach / size;
            let shifted: Vec<f64> = (0..n).map(|i| u[i] + h * x[i]).collect();
            if !this.energy_gradient(terms, &shifted, cx).is_finite() {
                return None;
            }
            Some(
                (0..n)
                    .map(|i| (this.g[i] - g0[i]) / h + mu[0] * this.rows[0][i] + mu[1] * this.rows[1][i])
                    .collect(),
            )
        };
        let result = (|| {
            // the Newton equation's residual at the symmetric update
            let a0 = apply(self, du, lam)?;
            let rho: Vec<f64> = (0..n).map(|i| -g0[i] - a0[i]).collect();
            let beta = dot(&rho, &rho).sqrt();
            // the residual at u with the current multipliers (g alone carries the hinge's reaction)
            let g_norm = (0..n)
                .map(|i| (g0[i] + current[0] * self.rows[0][i] + current[1] * self.rows[1][i]).powi(2))
                .sum::<f64>()
                .sqrt();
            if beta.is_nan() || beta <= KRYLOV_TOLERANCE * g_norm {
                return None;
            }
            let mut v: Vec<Vec<f64>> = vec![rho.iter().map(|x| x / beta).collect()];
            let mut z: Vec<(Vec<f64>, [f64; 2])> = Vec::new();
            let mut hess = [[0.0f64; KRYLOV_DIMENSION]; KRYLOV_DIMENSION + 1];
            let mut best = None;
            for j in 0..KRYLOV_DIMENSION {
                self.rhs[..n].copy_from_slice(&v[j]);
                let (x, mu) = self.saddle_solve(None, dphi, turn);
                let mut w = apply(self, &x, mu)?;
                z.push((x, mu));
                for i in 0..=j {
                    hess[i][j] = dot(&w, &v[i]);
                    for k in 0..n {
                        w[k] -= hess[i][j] * v[i][k];
                    }
                }
                hess[j + 1][j] = dot(&w, &w).sqrt();
                // least squares min ‖β e₁ − H y‖ over the (j+2) × (j+1) Hessenberg matrix, by
                // normal equations (at most 4 × 4)
                let m = j + 1;
                let mut a = vec![vec![0.0; m]; m];
                let mut b = vec![0.0; m];
                for p in 0..m {
                    b[p] = beta * hess[0][p];
                    for q in 0..m {
                        a[p][q] = (0..=m).map(|r| hess[r][p] * hess[r][q]).sum();
                    }
                }
                let y = solve_small(a, b)?;
                let resid: f64 = (0..=m)
                    .map(|r| {
                        let hy: f64 = (0..m).map(|q| hess[r][q] * y[q]).sum();
                        let e = if r == 0 { beta } else { 0.0 };
                        (e - hy).powi(2)
                    })
                    .sum::<f64>()
                    .sqrt();
                best = Some((y, resid));
                if resid <= KRYLOV_TOLERANCE * beta || hess[j + 1][j] <= 1e-14 * beta {
                    break;
                }
                v.push(w.iter().map(|x| x / hess[j + 1][j]).collect());
            }
            let (y, resid) = best?;
            if resid > 0.5 * beta {
                return None;
            }
            let mut out = du.to_vec();
            let mut l = lam;
            for (q, (x, mu)) in z.iter().enumerate().take(y.len()) {
                for i in 0..n {
                    out[i] += y[q] * x[i];
                }
                l[0] += y[q] * mu[0];
                l[1] += y[q] * mu[1];
            }
            Some((out, l))
        })();
        self.g = g0;
        result
    }

    /// Minimises `Σ terms` at time `t` from the feasible `u`; on success `u` and `lambda` hold the
    /// solution and its multipliers.
    ///
    /// **Tangent reuse.** The strain energy is objective, so the tangent of a rigidly rotated
    /// state is `Q K Qᵀ` with `Q` the rotation of every node's two components, and the mass term
    /// commutes with `Q`. A factorisation made in an earlier step at proxy angle `φ_f` therefore
    /// serves the current step at angle `φ` (`settings.frame_angle`) as `K⁻¹ ≈ Q K_f⁻¹ Qᵀ`,
    /// `Q = Q(φ − φ_f)`; it differs from the true tangent only by the change of the elastic state.
    /// Convergence is certified exactly as with a fresh tangent (`δ² < tolerance` and the residual
    /// check), and the solver refactorises at the current point when a reused factorisation
    /// contracts the residual by less than [`REFACTOR_CONTRACTION`] per iteration, when it proposes
    /// an update above the energy tolerance, when the matrix key (`settings.matrix_key`, the mass
    /// factor `1/(βΔt²)`) changes, or when `settings.reuse` is off.
    pub fn minimize(
        &mut self,
        pattern: &Pattern,
        terms: &[&dyn Term],
        cx: &StepContext,
        u: &mut [f64],
        lambda: &mut [f64; 2],
        settings: &NewtonSettings,
    ) -> Result<NewtonReport, NewtonError> {
        let n = pattern.n;
        let mut report = NewtonReport::default();
        let mut phi = Some(self.energy_gradient(terms, u, cx));
        if !phi.is_some_and(f64::is_finite) {
            return Err(NewtonError::NonFinite { iteration: 0 });
        }
        let mut r_prev = residual_norm_of(&self.g, &self.rows, *lambda);
        let mut need_factor = !settings.reuse || self.factor_frame.is_none_or(|(_, key)| key != settings.matrix_key);
        let mut k_at_u = false; // self.k holds the Hessian at u
        let mut factor_at_u = false; // the factorisation was made at u
        for iteration in 1..=settings.max_iterations {
            if need_factor {
                if !k_at_u {
                    phi = Some(self.assemble(pattern, terms, u, cx));
                    k_at_u = true;
                }
                self.factorize(pattern, settings, iteration, &mut report)?;
                need_factor = false;
                factor_at_u = true;
            }
            let (frame, _) = self.factor_frame.expect("a factorisation exists");
            let dphi = wrap_angle(settings.frame_angle - frame);
            let (du, lam, decrement) = self.constrained_solve(u, dphi, 0.0);
            report.iterations = iteration;
            report.decrements.push(decrement);
            if !decrement.is_finite() {
                return Err(NewtonError::NonFinite { iteration });
            }
            if decrement.abs() < settings.tolerance {
                u.iter_mut().zip(&du).for_each(|(x, d)| *x += d);
                *lambda = lam;
                report.step_lengths.push(1.0);
                (k_at_u, factor_at_u, phi) = (false, false, None);
                // Equilibrium at the accepted point, from a gradient-only evaluation.
                self.gradient_only(terms, u, cx);
                let r = residual_norm_of(&self.g, &self.rows, lam);
                report.residual = r;
                if r <= self.residual_bound(settings) || self.stagnated_at_rounding(terms, u, cx, lam, r, r_prev) {
                    return Ok(report);
                }
                if r > REFACTOR_CONTRACTION * r_prev {
                    need_factor = true;
                }
                r_prev = r;
                continue;
            }
            if !factor_at_u {
                // A reused factorisation proposes an update above the tolerance: take it if it
                // decreases Φ (energy and gradient at the trial point, no Hessian); otherwise
                // refactorise at u and redo the iteration with the true tangent.
                let phi0 = match phi {
                    Some(p) => p,
                    None => Self::energy(terms, u, cx),
                };
                for i in 0..n {
                    self.trial[i] = u[i] + du[i];
                }
                let g_saved = self.g.clone();
                let trial = std::mem::take(&mut self.trial);
                let phi_trial = self.energy_gradient(terms, &trial, cx);
                self.trial = trial;
                let rounding = 1e-13 * phi0.abs().max(decrement);
                if phi_trial.is_finite()
                    && (phi_trial <= phi0 - 1e-4 * decrement || (phi_trial - phi0).abs() <= rounding)
                {
                    u.copy_from_slice(&self.trial);
                    *lambda = lam;
                    report.step_lengths.push(1.0);
                    (phi, k_at_u) = (Some(phi_trial), false);
                    let r = residual_norm_of(&self.g, &self.rows, lam);
                    if r > REFACTOR_CONTRACTION * r_prev {
                        need_factor = true;
                    }
                    r_prev = r;
                } else {
                    self.g = g_saved;
                    phi = Some(phi0);
                    need_factor = true;
                }
                continue;
            }
            // A large update with the true tangent: line search on Φ.
            let phi0 = match phi {
                Some(p) => p,
                None => Self::energy(terms, u, cx),
            };
            let residual = residual_norm_of(&self.g, &self.rows, *lambda);
            let rounding = 1e-13 * phi0.abs().max(decrement);
            let mut step = 1.0;
            let mut accepted = None;
            for trial_no in 0..40 {
                for i in 0..n {
                    self.trial[i] = u[i] + step * du[i];
                }
                // The first trial is a full assembly, reused by the next iteration when accepted.
                let phi_trial = if trial_no == 0 {
                    let trial = std::mem::take(&mut self.trial);
                    let p = self.assemble(pattern, terms, &trial, cx);
                    self.trial = trial;
                    p
                } else {
                    let start = std::time::Instant::now();
                    let p = Self::energy(terms, &self.trial, cx);
                    self.timings.line_search += start.elapsed().as_secs_f64();
                    p
                };
                if phi_trial.is_finite()
                    && (phi_trial <= phi0 - 1e-4 * step * decrement || (phi_trial - phi0).abs() <= rounding)
                {
                    if trial_no > 0 {
                        let trial = std::mem::take(&mut self.trial);
                        self.assemble(pattern, terms, &trial, cx);
                        self.trial = trial;
                    }
                    accepted = Some(phi_trial);
                    break;
                }
                step *= 0.5;
            }
            let Some(phi_new) = accepted else {
                return Err(NewtonError::LineSearch { iteration, residual });
            };
            u.copy_from_slice(&self.trial);
            for (l, ln) in lambda.iter_mut().zip(lam) {
                *l += step * (ln - *l);
            }
            report.step_lengths.push(step);
            (phi, k_at_u, factor_at_u, need_factor) = (Some(phi_new), true, false, true);
            r_prev = residual_norm_of(&self.g, &self.rows, *lambda);
        }
        let last = report.decrements.last().copied().unwrap_or(f64::NAN);
        let residual = residual_norm_of(&self.g, &self.rows, *lambda);
        Err(NewtonError::MaxIterations {
            iterations: settings.max_iterations,
            energy_norm: last,
            residual,
            forces: self.forces_in_play(terms, u, cx, *lambda),
        })
    }

    /// Solves the system `r(u) + Cᵀλ = 0`, `C u = 0`, where `r` is the sum of the terms' gradients
    /// and no potential exists (the energy-momentum step, [`crate::energy_momentum`]). The sum of
    /// the terms' Hessians serves as a symmetric approximation of the Jacobian `∂r/∂u` (factorised
    /// and reused exactly as in [`Solver::minimize`]); the terms' energies only flag inadmissible
    /// states (`+∞`).
    ///
    /// Each iteration solves for the update, evaluates `r` at `u + sΔu` (`s = 1` first) and takes
    /// it when the residual `‖r + Cᵀλ‖∞` decreases or is already within the bound, or when the
    /// simplified correction there is shorter in the tangent's energy norm than the update by the
    /// factor `(1 − s/4)²` (Deuflhard's natural monotonicity test); otherwise it refactorises at
    /// `u` (a reused factorisation) or halves `s`. A reused factorisation is renewed when it
    /// contracts the residual by less than [`REFACTOR_CONTRACTION`], or when at its contraction it
    /// would need more than [`REUSE_HORIZON`] further iterations. It has converged when the update
    /// satisfies `δ² = Δuᵀ K̃ Δu < tolerance` (the criterion of [`Solver::minimize`]), the residual
    /// is within `residual_tolerance · load_scale` (with its rounding floor), and, with `energy`
    /// given as `(u₀, bound)`, `|½ (u − u₀) · r(u)| ≤ bound`: for the energy-momentum step that is
    /// exactly the error of the step's energy balance \[J\].
    ///
    /// The symmetric tangent leaves out the unsymmetric part of the discrete gradient's Jacobian
    /// (the mid-step stress and deformation gradient against the end-of-step ones), an error of
    /// the order of the strain the step changes. For the tutorial's swing that is 1e-3 and
    /// below; after a blow, in the ringing it leaves (strains near 0.1 in a soft head), every
    /// iteration, with a fresh tangent or not, contracted the residual by only 0.02–0.1, and a
    /// step took 8–11 iterations or ran out of them and was cut back. So once an iteration
    /// contracts by less than [`SLOW_CONTRACTION`], every later update of the solve is corrected
    /// by GMRES on the Newton equation with the system's own Jacobian, applied by differences of
    /// the gradient and preconditioned by the same factorisation (at most [`KRYLOV_DIMENSION`]
    /// products, to [`KRYLOV_TOLERANCE`]): the contraction becomes 1e-4–1e-3.
    ///
    /// With `correct` false the updates are never corrected: a step's last attempt, where a
    /// failure is no longer cut back, goes without the correction (its updates can reach a state
    /// whose tangent is indefinite, or stall, where the plain iteration goes on: a soft head,
    /// seed 18's case 12 of `tests/robustness.rs`; see [`crate::simulation::Simulation::step`]).
    // the system (pattern, terms, time), the unknowns (u, λ), the settings, the energy check and
    // whether to correct
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        pattern: &Pattern,
        terms: &[&dyn Term],
        cx: &StepContext,
        u: &mut [f64],
        lambda: &mut [f64; 2],
        settings: &NewtonSettings,
        energy: Option<(&[f64], f64)>,
        correct: bool,
    ) -> Result<NewtonReport, NewtonError> {
        let n = pattern.n;
        let mut report = NewtonReport::default();
        if !self.energy_gradient(terms, u, cx).is_finite() {
            return Err(NewtonError::NonFinite { iteration: 0 });
        }
        let mut r_prev = residual_norm_of(&self.g, &self.rows, *lambda);
        let mut need_factor = !settings.reuse || self.factor_frame.is_none_or(|(_, key)| key != settings.matrix_key);
        let mut factor_at_u = false;
        let mut iteration = 0;
        let mut e_prev = f64::INFINITY;
        // whether an iteration of this solve contracted the residual by less than SLOW_CONTRACTION
        let mut slow = false;
        let mut watchdog = Watchdog::new(u, *lambda, r_prev);
        // whether `self.g` holds the gradient at `u` (not at a trial point the line search left,
        // nor at a point the watchdog left): a tangent made at `u` then needs only the Hessian
        let mut gradient_at_u = true;
        while iteration < settings.max_iterations {
            iteration += 1;
            if need_factor {
                if gradient_at_u {
                    self.assemble_hessian(pattern, terms, u, cx);
                } else {
                    self.assemble(pattern, terms, u, cx);
                    gradient_at_u = true;
                }
                self.factorize(pattern, settings, iteration, &mut report)?;
                need_factor = false;
                factor_at_u = true;
            }
            let (frame, _) = self.factor_frame.expect("a factorisation exists");
            let dphi = wrap_angle(settings.frame_angle - frame);
            let (mut du, mut lam, decrement) = self.constrained_solve(u, dphi, settings.residual_turn);
            if slow && correct {
                if let Some((d, l)) = self.krylov_refine(
                    terms,
                    cx,
                    u,
                    (&du, lam, *lambda),
                    (dphi, settings.residual_turn),
                    settings.length_scale,
                ) {
                    (du, lam) = (d, l);
                }
            }
            report.iterations = iteration;
            report.decrements.push(decrement);
            if !decrement.is_finite() {
                return Err(NewtonError::NonFinite { iteration });
            }
            let bound = self.residual_bound(settings);
            let mut step = 1.0;
            // whether the step was taken whole on the watchdog's allowance
            let mut forced = false;
            let accepted = loop {
                for i in 0..n {
                    self.trial[i] = u[i] + step * du[i];
                }
                let lam_trial = [0, 1].map(|k| lambda[k] + step * (lam[k] - lambda[k]));
                let trial = std::mem::take(&mut self.trial);
                let admissible = self.energy_gradient(terms, &trial, cx).is_finite();
                self.trial = trial;
                let r = residual_norm_of(&self.g, &self.rows, lam_trial);
                if admissible && (r < r_prev || r <= bound) {
                    break Some((lam_trial, r));
                }
                // Deuflhard's natural monotonicity test: the simplified correction at the trial
                // point (the same factorisation) is shorter, in the tangent's energy norm, than
                // the correction that led there. Inside an impact the largest nodal residual
                // moves between nodes from one iterate to the next (the contact's active points
                // change), and a full step that the norm of the tangent shows to be sound was
                // halved again and again by the maximum norm alone.
                if admissible {
                    let trial = std::mem::take(&mut self.trial);
                    let (_, _, simplified) = self.constrained_solve(&trial, dphi, settings.residual_turn);
                    self.trial = trial;
                    if simplified.abs() <= (1.0 - 0.25 * step).powi(2) * decrement.abs() {
                        break Some((lam_trial, r));
                    }
                    if step == 1.0 && factor_at_u && watchdog.allows() {
                        forced = true;
                        break Some((lam_trial, r));
                    }
                }
                if !factor_at_u || step < 1e-3 {
                    break None;
                }
                step *= 0.5;
            };
            let Some((lam_new, r)) = accepted else {
                if factor_at_u {
                    return Err(NewtonError::LineSearch {
                        iteration,
                        residual: r_prev,
                    });
                }
                // a reused factorisation led astray: redo the iteration with the tangent at u
                need_factor = true;
                gradient_at_u = false;
                continue;
            };
            u.copy_from_slice(&self.trial);
            *lambda = lam_new;
            if watchdog.must_return(u, *lambda, r) {
                u.copy_from_slice(&watchdog.u);
                *lambda = watchdog.lambda;
                r_prev = watchdog.residual;
                (need_factor, factor_at_u, gradient_at_u) = (true, false, false);
                continue;
            }
            report.step_lengths.push(step);
            report.residual = r;
            // the energy balance is met, or it has stopped improving at a residual within the
            // bound under a tangent made at this iteration's start (rounding: the last iteration
            // did not halve it). A reused factorisation that stalls is renewed instead: the
            // residual bound is loose for the energy (at 1e-4 of the nodal loads, a fast spin's
            // balance can stall at 1e-8 of its energy per step), a fresh tangent is not.
            let mut renew = false;
            // how far the criteria are from being met, as a factor (≤ 1: met)
            let mut distance = r / bound;
            let balanced = match energy {
                Some((u0, limit)) => {
                    let e = (0..n).map(|i| (u[i] - u0[i]) * self.g[i]).sum::<f64>().abs() * 0.5;
                    let stalled = r_prev <= bound && e >= 0.5 * e_prev;
                    e_prev = e;
                    renew = e > limit && stalled && !factor_at_u;
                    distance = distance.max(e / limit);
                    e <= limit || (stalled && factor_at_u && e <= STALLED_ENERGY * limit)
                }
                None => true,
            };
            // a reused factorisation whose contraction would need more than REUSE_HORIZON further
            // iterations to meet the criteria is renewed: inside an impact it contracts steadily
            // but slowly (0.3–0.5 per iteration, the contact's and the strain's change since it
            // was made), and a step then ran out of iterations with its residual far below the
            // forces in play, to be cut back again and again; a fresh tangent contracts by 0.01–0.1
            if !factor_at_u && distance > 1.0 && r_prev > 0.0 {
                let contraction = r / r_prev;
                renew |= contraction >= 1.0 || distance.ln() > REUSE_HORIZON * -contraction.ln();
            }
            if step == 1.0
                && decrement.abs() < settings.tolerance
                && balanced
                && (r <= bound || self.stagnated_at_rounding(terms, u, cx, *lambda, r, r_prev))
            {
                return Ok(report);
            }
            // a reused factorisation that contracts slowly is renewed (not once the residual is
            // within the bound: then only the energy balance is being tightened)
            if (r > REFACTOR_CONTRACTION * r_prev && r > bound && !factor_at_u) || renew || forced {
                need_factor = true;
            }
            factor_at_u = false;
            slow |= r > SLOW_CONTRACTION * r_prev;
            r_prev = r;
        }
        let last = report.decrements.last().copied().unwrap_or(f64::NAN);
        Err(NewtonError::MaxIterations {
            iterations: settings.max_iterations,
            energy_norm: last,
            residual: r_prev,
            forces: self.forces_in_play(terms, u, cx, *lambda),
        })
    }

    /// The gradient `∇Φ` of the last assembly (a view for diagnostics).
    pub fn gradient(&self) -> &[f64] {
        &self.g
    }
}
