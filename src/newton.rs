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

use crate::assembly::Pattern;
use crate::constraint::Hinge;
use crate::error::NewtonError;
use crate::linsolve::Cholesky;
use crate::terms::Term;
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
    /// Gradient-only evaluations for the final residual check.
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
    /// Accumulated timings.
    pub timings: Timings,
}

fn residual_norm_of(g: &[f64], rows: &[Vec<f64>; 2], lam: [f64; 2]) -> f64 {
    (0..g.len())
        .map(|i| (g[i] + rows[0][i] * lam[0] + rows[1][i] * lam[1]).abs())
        .fold(0.0, f64::max)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Solver {
    /// Symbolic analysis of `pattern` and buffers for the hinge `hinge`.
    pub fn new(pattern: &Pattern, hinge: &Hinge) -> Result<Self, Error> {
        let n = pattern.n;
        let chol = Cholesky::new(pattern)?;
        Ok(Self {
            rows: hinge.dense_rows(n),
            g: vec![0.0; n],
            k: vec![0.0; pattern.nnz()],
            rhs: vec![0.0; 3 * n],
            trial: vec![0.0; n],
            chol,
            timings: Timings::default(),
        })
    }

    /// Stored entries of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.chol.factor_nnz()
    }

    fn energy(terms: &[&dyn Term], u: &[f64], t: f64) -> f64 {
        terms.iter().map(|term| term.energy(u, t)).sum()
    }

    fn assemble(&mut self, pattern: &Pattern, terms: &[&dyn Term], u: &[f64], t: f64) -> f64 {
        let start = std::time::Instant::now();
        self.g.iter_mut().for_each(|x| *x = 0.0);
        self.k.iter_mut().for_each(|x| *x = 0.0);
        let mut phi = 0.0;
        for term in terms {
            phi += term.assemble(u, t, pattern, &mut self.g, &mut self.k);
        }
        self.timings.assembly += start.elapsed().as_secs_f64();
        phi
    }

    /// Minimises `Σ terms` at time `t` from the feasible `u`; on success `u` and `lambda` hold the
    /// solution and its multipliers.
    ///
    /// After an update with `δ² < tolerance` the residual is checked at the new point. If it is
    /// still too large, the next iteration reuses the current factorisation with the fresh gradient
    /// (a modified-Newton step: the update was below the energy tolerance, so the tangent has not
    /// changed appreciably); otherwise every iteration refactorises.
    pub fn minimize(
        &mut self,
        pattern: &Pattern,
        terms: &[&dyn Term],
        t: f64,
        u: &mut [f64],
        lambda: &mut [f64; 2],
        settings: &NewtonSettings,
    ) -> Result<NewtonReport, NewtonError> {
        let n = pattern.n;
        let mut report = NewtonReport::default();
        let mut phi = self.assemble(pattern, terms, u, t);
        if !phi.is_finite() {
            return Err(NewtonError::NonFinite { iteration: 0 });
        }
        // true: K (and its factorisation to come) belong to `u`; false: reuse the last factorisation.
        let mut fresh_tangent = true;
        for iteration in 1..=settings.max_iterations {
            if fresh_tangent {
                let start = std::time::Instant::now();
                let factored = self.chol.factor(pattern, &self.k);
                self.timings.factorization += start.elapsed().as_secs_f64();
                report.factorizations += 1;
                if factored.is_err() {
                    return Err(NewtonError::SingularTangent { iteration });
                }
            }
            let start = std::time::Instant::now();
            // Columns: −g, Cᵀ row x, Cᵀ row y.
            for i in 0..n {
                self.rhs[i] = -self.g[i];
            }
            self.rhs[n..2 * n].copy_from_slice(&self.rows[0]);
            self.rhs[2 * n..].copy_from_slice(&self.rows[1]);
            self.chol.solve_in_place(&mut self.rhs);
            let (y, z) = self.rhs.split_at(n);
            let (zx, zy) = z.split_at(n);
            let s = [
                [dot(&self.rows[0], zx), dot(&self.rows[0], zy)],
                [dot(&self.rows[1], zx), dot(&self.rows[1], zy)],
            ];
            // C(u + Δu) = 0 with Δu = y − Zλ  ⇒  S λ = C y + C u.
            let b = [
                dot(&self.rows[0], y) + dot(&self.rows[0], u),
                dot(&self.rows[1], y) + dot(&self.rows[1], u),
            ];
            let det = s[0][0] * s[1][1] - s[0][1] * s[1][0];
            let lam = [
                (b[0] * s[1][1] - b[1] * s[0][1]) / det,
                (s[0][0] * b[1] - s[1][0] * b[0]) / det,
            ];
            let du: Vec<f64> = (0..n).map(|i| y[i] - zx[i] * lam[0] - zy[i] * lam[1]).collect();
            let decrement = -(dot(&du, &self.g) + lam[0] * dot(&self.rows[0], &du) + lam[1] * dot(&self.rows[1], &du));
            self.timings.solve += start.elapsed().as_secs_f64();
            report.iterations = iteration;
            report.decrements.push(decrement);
            if !decrement.is_finite() {
                return Err(NewtonError::NonFinite { iteration });
            }
            if decrement.abs() < settings.tolerance {
                u.iter_mut().zip(&du).for_each(|(x, d)| *x += d);
                *lambda = lam;
                report.step_lengths.push(1.0);
                // Equilibrium at the accepted point, from a gradient-only evaluation.
                let start = std::time::Instant::now();
                self.g.iter_mut().for_each(|x| *x = 0.0);
                for term in terms {
                    term.add_gradient(u, t, &mut self.g);
                }
                self.timings.residual += start.elapsed().as_secs_f64();
                report.residual = residual_norm_of(&self.g, &self.rows, lam);
                if report.residual <= settings.residual_tolerance * settings.load_scale {
                    return Ok(report);
                }
                fresh_tangent = false;
                continue;
            }
            // A large update: line search on Φ with fresh assemblies.
            if !fresh_tangent {
                phi = Self::energy(terms, u, t);
            }
            let residual = residual_norm_of(&self.g, &self.rows, *lambda);
            let rounding = 1e-13 * phi.abs().max(decrement);
            let mut step = 1.0;
            let mut accepted = false;
            for trial_no in 0..40 {
                for i in 0..n {
                    self.trial[i] = u[i] + step * du[i];
                }
                // The first trial is a full assembly, reused by the next iteration when accepted.
                let phi_trial = if trial_no == 0 {
                    let trial = std::mem::take(&mut self.trial);
                    let p = self.assemble(pattern, terms, &trial, t);
                    self.trial = trial;
                    p
                } else {
                    let start = std::time::Instant::now();
                    let p = Self::energy(terms, &self.trial, t);
                    self.timings.line_search += start.elapsed().as_secs_f64();
                    p
                };
                if phi_trial.is_finite()
                    && (phi_trial <= phi - 1e-4 * step * decrement || (phi_trial - phi).abs() <= rounding)
                {
                    if trial_no > 0 {
                        let trial = std::mem::take(&mut self.trial);
                        self.assemble(pattern, terms, &trial, t);
                        self.trial = trial;
                    }
                    phi = phi_trial;
                    accepted = true;
                    break;
                }
                step *= 0.5;
            }
            if !accepted {
                return Err(NewtonError::LineSearch { iteration, residual });
            }
            u.copy_from_slice(&self.trial);
            for (l, ln) in lambda.iter_mut().zip(lam) {
                *l += step * (ln - *l);
            }
            report.step_lengths.push(step);
            fresh_tangent = true;
        }
        let last = report.decrements.last().copied().unwrap_or(f64::NAN);
        let residual = residual_norm_of(&self.g, &self.rows, *lambda);
        Err(NewtonError::MaxIterations {
            iterations: settings.max_iterations,
            energy_norm: last,
            residual,
        })
    }

    /// The gradient `∇Φ` of the last assembly (a view for diagnostics).
    pub fn gradient(&self) -> &[f64] {
        &self.g
    }
}
