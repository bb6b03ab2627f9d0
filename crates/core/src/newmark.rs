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

/// Kinematic state at one time: nodal displacement, velocity and acceleration (interleaved).
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Time \[s\].
    pub t: f64,
    /// Displacement \[m\].
    pub u: Vec<f64>,
    /// Velocity \[m/s\].
    pub v: Vec<f64>,
    /// Acceleration \[m/s²\].
    pub a: Vec<f64>,
}

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
