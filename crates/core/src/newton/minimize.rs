//! [`Solver::minimize`]: Newton's method with a backtracking line search for `min Φ(u)` under the
//! hinge, with the reuse of a factorisation made in an earlier frame.

use super::evaluate::residual_norm_of;
use super::{NewtonReport, NewtonSettings, Solver, REFACTOR_CONTRACTION};
use crate::assembly::Pattern;
use crate::error::NewtonError;
use crate::rigid::wrap_angle;
use crate::terms::{StepContext, Term};

impl Solver {
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
}
