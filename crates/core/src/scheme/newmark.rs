//! Newmark-β time integration written as an incremental potential.
//!
//! With predictors `ũ = uₙ + Δt vₙ + Δt²(½ − β) aₙ` and `ṽ = vₙ + Δt(1 − γ) aₙ`, the new displacement
//! minimises
//!
//! ```text
//! Φ(u) = 1/(2βΔt²) (u − ũ)ᵀ M (u − ũ) + Π(u, tₙ₊₁)   subject to  c(u) = 0,
//! ```
//!
//! and then `aₙ₊₁ = (u − ũ)/(βΔt²)`, `vₙ₊₁ = ṽ + γΔt aₙ₊₁`. The integrator knows nothing about
//! elasticity, hinges or contact.
//!
//! **HHT-α** (Hilber, Hughes and Taylor, 1977) weights the forces of the two ends of the step,
//! `M aₙ₊₁ + (1 + α) ∇Π(uₙ₊₁, tₙ₊₁) − α ∇Π(uₙ, tₙ) = 0` (multipliers likewise), with
//! `β = (1 − α)²/4`, `γ = ½ − α`, `−⅓ ≤ α ≤ 0`. It is again an incremental potential,
//! `Φ(u) = 1/(2βΔt²) (u − ũ)ᵀ M (u − ũ) + (1 + α) Π(u, tₙ₊₁) − α ∇Π(uₙ, tₙ)·u`, second order, and
//! damps the modes that the step does not resolve; `α = 0` is the average-acceleration rule.
//!
//! The average-acceleration preset (β = ¼, γ = ½) is exactly the
//! tutorial's update `v⁺ = 2/Δt (u⁺ − u) − v`, `a⁺ = 2/Δt (v⁺ − v) − a`.

use super::{Iterate, Start, Stepped, TimeScheme, RESIDUAL_TOLERANCE};
use crate::error::NewtonError;
use crate::model::State;
use crate::newton::{NewtonSettings, Solver};
use crate::terms::{Inertia, Linear, Scaled, StepContext, Term};

/// Newmark parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Newmark {
    /// β.
    pub beta: f64,
    /// γ.
    pub gamma: f64,
}

impl Newmark {
    /// Trapezoidal rule (β = ¼, γ = ½): unconditionally stable, second order, energy-conserving for
    /// linear problems. The tutorial's scheme and the default.
    pub const AVERAGE_ACCELERATION: Self = Self { beta: 0.25, gamma: 0.5 };
    /// β = 1/6, γ = ½: conditionally stable, second order.
    pub const LINEAR_ACCELERATION: Self = Self {
        beta: 1.0 / 6.0,
        gamma: 0.5,
    };

    /// The Newmark parameters of HHT-α (`β = (1 − α)²/4`, `γ = ½ − α`).
    pub fn hht(alpha: f64) -> Self {
        Self {
            beta: (1.0 - alpha) * (1.0 - alpha) / 4.0,
            gamma: 0.5 - alpha,
        }
    }

    /// `ũ = uₙ + Δt vₙ + Δt²(½ − β) aₙ`.
    pub fn predict_u(&self, dt: f64, s: &State) -> Vec<f64> {
        let c = dt * dt * (0.5 - self.beta);
        s.u.iter()
            .zip(&s.v)
            .zip(&s.a)
            .map(|((u, v), a)| u + dt * v + c * a)
            .collect()
    }

    /// `1/(βΔt²)`, the factor of the mass matrix in the incremental potential.
    pub fn inertia_factor(&self, dt: f64) -> f64 {
        1.0 / (self.beta * dt * dt)
    }

    /// The state at `t + Δt` from the minimiser `u_new`.
    pub fn correct(&self, dt: f64, old: &State, u_new: Vec<f64>) -> State {
        let u_pred = self.predict_u(dt, old);
        let f = self.inertia_factor(dt);
        let a: Vec<f64> = u_new.iter().zip(&u_pred).map(|(u, p)| f * (u - p)).collect();
        let v = old
            .v
            .iter()
            .zip(&old.a)
            .zip(&a)
            .map(|((v, a0), a1)| v + dt * ((1.0 - self.gamma) * a0 + self.gamma * a1))
            .collect();
        State {
            t: old.t + dt,
            u: u_new,
            v,
            a,
        }
    }
}

/// The Newmark family as a time scheme: HHT-α with its Newmark parameters; `α = 0` is the
/// trapezoidal rule (the average-acceleration preset).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hht {
    /// α, `−⅓ ≤ α ≤ 0`.
    pub alpha: f64,
    /// `β = (1 − α)²/4`, `γ = ½ − α`.
    pub newmark: Newmark,
}

impl Hht {
    /// HHT-α with its Newmark parameters ([`Newmark::hht`]).
    pub fn new(alpha: f64) -> Self {
        Self {
            alpha,
            newmark: Newmark::hht(alpha),
        }
    }
}

impl TimeScheme for Hht {
    fn step(
        &self,
        start: &Start,
        dt: f64,
        mut u: Vec<f64>,
        solver: &mut Solver,
        _iterate: Iterate,
    ) -> Result<Stepped, NewtonError> {
        let m = start.model;
        let state = start.state;
        let t_new = state.t + dt;
        let cx = StepContext {
            t: t_new,
            t0: state.t,
            dt,
            u0: &state.u,
            theta0: start.theta,
            torque: start.held_torque,
        };
        let inertia = Inertia {
            mass: &m.mass,
            pattern: &m.pattern,
            factor: self.newmark.inertia_factor(dt),
            predictor: self.newmark.predict_u(dt, state),
        };
        let mut physical: Vec<&dyn Term> = m.body_terms(0.0).into_iter().map(|(t, _)| t).collect();
        physical.extend(m.loads());
        // HHT-α: (1 + α) Π(u, tₙ₊₁) − α ∇Π(uₙ, tₙ)·u; plain terms for the trapezoidal rule.
        let alpha = self.alpha;
        let scaled: Vec<Scaled> = physical
            .iter()
            .map(|&term| Scaled {
                term,
                factor: 1.0 + alpha,
            })
            .collect();
        let mut previous = Linear::new(Vec::new());
        let mut terms: Vec<&dyn Term> = vec![&inertia];
        if alpha == 0.0 {
            terms.extend(physical.iter().copied());
        } else {
            previous.load_gradient = vec![0.0; state.u.len()];
            let at_start = StepContext::at(&state.u, state.t, start.theta, start.held_torque);
            for term in &physical {
                term.add_gradient(&state.u, &at_start, &mut previous.load_gradient);
            }
            previous.load_gradient.iter_mut().for_each(|g| *g *= -alpha);
            terms.extend(scaled.iter().map(|t| t as &dyn Term));
            terms.push(&previous);
        }
        let mut lambda = start.lambda;
        let settings = NewtonSettings {
            tolerance: m.config.solver.tolerance,
            max_iterations: m.config.solver.max_iterations,
            residual_tolerance: RESIDUAL_TOLERANCE,
            load_scale: start.load_scale,
            length_scale: m.length_scale(),
            frame_angle: m.projection.angle(&u),
            matrix_key: self.newmark.inertia_factor(dt) / (1.0 + alpha),
            reuse: true,
            residual_turn: 0.0,
        };
        let report = solver.minimize(&m.pattern, &terms, &cx, &mut u, &mut lambda, &settings)?;
        Ok(Stepped {
            state: self.newmark.correct(dt, state, u),
            lambda,
            iterations: report.iterations,
            factorizations: report.factorizations,
        })
    }

    fn uses_elastic_starts(&self) -> bool {
        false
    }

    fn keeps_mean_acceleration(&self) -> bool {
        false
    }

    fn retries_uncorrected(&self) -> bool {
        false
    }

    fn extrapolates_shape(&self) -> bool {
        false
    }
}
