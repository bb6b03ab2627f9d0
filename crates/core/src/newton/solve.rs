//! [`Solver::solve`]: Newton's method for a system without a potential (the energy-momentum
//! step), with the natural monotonicity test, the watchdog ([`WATCHDOG_STEPS`]), the energy
//! balance criterion and the GMRES correction of slow iterations.

use super::evaluate::residual_norm_of;
use super::{
    NewtonReport, NewtonSettings, Solver, REFACTOR_CONTRACTION, REUSE_HORIZON, SLOW_CONTRACTION, STALLED_ENERGY,
    WATCHDOG_STEPS,
};
#[cfg(doc)]
use super::{KRYLOV_DIMENSION, KRYLOV_TOLERANCE};
use crate::assembly::Pattern;
use crate::error::NewtonError;
use crate::rigid::wrap_angle;
use crate::terms::{StepContext, Term};

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

impl Solver {
    /// Solves the system `r(u) + Cᵀλ = 0`, `C u = 0`, where `r` is the sum of the terms' gradients
    /// and no potential exists (the energy-momentum step, [`crate::scheme::energy_momentum`]). The sum of
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
}
