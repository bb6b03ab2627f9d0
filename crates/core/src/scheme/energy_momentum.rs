//! The energy-momentum time integrator: the midpoint rule with a discrete gradient.
//!
//! With `Π` the sum of the terms (strain energy, gravity, torque), `C` the hinge rows and a step
//! `tₙ → tₙ₊₁ = tₙ + Δt`:
//!
//! ```text
//! u₁ − u₀ = Δt (v₀ + v₁)/2
//! M (v₁ − v₀)/Δt + ∇ᵈΠ(u₀, u₁) + Cᵀλ = 0,        C u₁ = 0,
//! ```
//!
//! `λ` the mean hinge force over the step. `∇ᵈΠ` is a discrete gradient ([`crate::terms`]): for the
//! strain energy Gonzalez's formula in the Green–Lagrange strain (objective: a rigid rotation of any
//! size produces no strain and no stress), for gravity and the fixed-direction load the gradient
//! itself (they are linear), for the follower torque `−M̄ ∇ᵈθ_hub`. Then, exactly for any `Δt`:
//!
//! * **Energy.** With `E = ½ vᵀM v + Π`: `E₁ − E₀ = v_m·M Δv + ∇ᵈΠ·Δu = (Δu/Δt)·(M Δv + Δt ∇ᵈΠ)
//!   = −λ·C Δu = 0`, `v_m = ½(v₀ + v₁) = Δu/Δt`. A torque adds its work `M̄ Δθ_hub`.
//! * **Angular momentum about the pivot.** `L = Σ_ab M_ab x_a × v_b`; with `x₁ = x₀ + Δt v_m` and `M`
//!   symmetric, `L₁ − L₀ = Σ_ab M_ab x_m,a × Δv_b = −Δt Σ_a x_m,a × (∇ᵈΠ + Cᵀλ)_a`. The strain
//!   energy's forces `F_m S_d` have no moment at the mid-step positions, the hinge's acts at the
//!   pivot (`∫_Γ x ds = 0`); what remains is the moment of gravity and the torque.
//!
//! Written in `u₁`, with `ũ = u₀ + Δt v₀` and the equation doubled so that its matrix is that of the
//! trapezoidal rule:
//!
//! ```text
//! r(u₁) = 4/Δt² M (u₁ − ũ) + 2 ∇ᵈΠ(u₀, u₁) + Cᵀ(2λ) = 0.
//! ```
//!
//! `r` is not the gradient of any potential (its Jacobian is not symmetric: `F_m` on one side,
//! `F₁` on the other), so [`crate::newton::Solver::solve`] iterates with the symmetric
//! `K̃ = 4/Δt² M + (1 + χ) ∇²Π(u₁)`, the trapezoidal rule's tangent, whose factorisation it reuses
//! across steps, and certifies convergence by the residual. In the stiff modes the Jacobian is
//! `≈ cos(Δφ/2) Q(−Δφ/2) K`: the material tangent seen from the mid-step frame, `Δφ` the turn of
//! the step and `Q` the rotation of every node's two components. The solver therefore turns the
//! residual by `Δφ/2` before the solve (and the multipliers back), which takes the contraction per
//! iteration from about `Δφ/2` to the change of the elastic state: two iterations per step for
//! the tutorial's swing instead of four. The energy error of a step is exactly
//! `½ (u₁ − u₀)·r(u₁)` (the work of the remaining residual); the solver keeps it below
//! `solver.energy_tolerance` times the step's energy scale ([`energy_scale`]).
//!
//! **Predictor.** The current configuration turned rigidly about the pivot by `Δφ` with
//! `tan(Δφ/2) = Δt ω̄/2`, `ω̄` the mean angular velocity of the step extrapolated from the rates:
//! the midpoint rule advances a rotation along the chord, and a guess that is off in the angle
//! costs a linearised rotation of the stiff body (a spurious stretch) in the first update.
//!
//! **Rates.** `v₁ = 2 (u₁ − u₀)/Δt − v₀`. The scheme needs no acceleration; the state keeps the
//! step's mean acceleration `(v₁ − v₀)/Δt` (a load scale for the next step), and the reported
//! angular acceleration is the consistent end-of-step value: the moment of the external loads at
//! `x₁` over `∫ ρ t |x₁|² dA` (the strain energy's and the hinge's forces have no moment).
//!
//! **Dissipation** (`time.dissipation = χ`, optional): the stress `(χ/2) ℂ₀:ΔE` is added to the
//! discrete stress, `ℂ₀` the isotropic tensor of the Lamé constants. It removes
//! `(χ/2) ΔE:ℂ₀:ΔE ≥ 0` per unit volume and step, keeps the angular momentum (the force is still
//! of the form `F_m S`), leaves rigid motion alone (`ΔE = 0`), and damps a mode that the step does
//! not resolve with the factor `(1 − χ)/(1 + χ)` per step; a resolved mode of frequency `ω` loses
//! about `π χ ω Δt` of its energy per period (first order). In the spirit of Armero and Romero's
//! energy-dissipative, momentum-conserving schemes; not their formula.

use super::{Iterate, Start, Stepped, TimeScheme, RESIDUAL_TOLERANCE};
use crate::error::NewtonError;
use crate::model::State;
use crate::newton::{NewtonSettings, Solver};
use crate::rigid::wrap_angle;
use crate::terms::{DiscreteGradient, Inertia, StepContext, StepStart, Term};

/// The energy-momentum scheme with the numerical dissipation `χ` (`time.dissipation`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyMomentum {
    /// `χ ∈ [0, 1)`.
    pub dissipation: f64,
}

impl EnergyMomentum {
    /// `4/Δt²`, the mass factor of the doubled equation.
    pub fn inertia_factor(dt: f64) -> f64 {
        4.0 / (dt * dt)
    }

    /// `ũ = u₀ + Δt v₀`.
    pub fn predictor(dt: f64, s: &State) -> Vec<f64> {
        s.u.iter().zip(&s.v).map(|(u, v)| u + dt * v).collect()
    }

    /// The state at `t + Δt` from the solution `u1`: `v₁ = 2 (u₁ − u₀)/Δt − v₀`, and as `a` the
    /// mean acceleration of the step `(v₁ − v₀)/Δt`.
    pub fn correct(dt: f64, old: &State, u1: Vec<f64>) -> State {
        let v: Vec<f64> = u1
            .iter()
            .zip(&old.u)
            .zip(&old.v)
            .map(|((u1, u0), v0)| 2.0 * (u1 - u0) / dt - v0)
            .collect();
        let a = v.iter().zip(&old.v).map(|(v1, v0)| (v1 - v0) / dt).collect();
        State {
            t: old.t + dt,
            u: u1,
            v,
            a,
        }
    }
}

/// The energy scale of a step \[J\]: the kinetic energy at its start, plus the weight times the
/// largest distance from the pivot (the range of the gravitational energy), plus `π |M|` for an
/// applied torque `M` (its work over half a turn). The solver keeps the energy error of every step
/// below `solver.energy_tolerance` times this scale ([`crate::newton::Solver::solve`]).
pub fn energy_scale(kinetic: f64, weight_times_radius: f64, torque: f64) -> f64 {
    kinetic.abs() + weight_times_radius.abs() + std::f64::consts::PI * torque.abs()
}

impl TimeScheme for EnergyMomentum {
    fn step(
        &self,
        start: &Start,
        dt: f64,
        mut u: Vec<f64>,
        solver: &mut Solver,
        iterate: Iterate,
    ) -> Result<Stepped, NewtonError> {
        let m = start.model;
        let (state, u0) = (start.state, &start.state.u);
        let (t0, t_new) = (state.t, state.t + dt);
        let cx = StepContext {
            t: t_new,
            t0,
            dt,
            u0,
            theta0: start.theta,
            torque: start.held_torque,
        };
        let chi = self.dissipation;
        let inertia = Inertia {
            mass: &m.mass,
            pattern: &m.pattern,
            factor: Self::inertia_factor(dt),
            predictor: Self::predictor(dt, state),
        };
        let mut physical: Vec<(&dyn Term, f64)> = m.body_terms(chi);
        physical.extend(m.loads().map(|t| (t, 1.0)));
        // the bodies' terms come first, each body's elastic term before its weight
        // (`Model::body_terms`); the elastic ones start from the data made for this state
        let starts: Vec<std::borrow::Cow<[f64]>> = physical
            .iter()
            .enumerate()
            .map(|(k, (t, _))| match start.elastic.get(k / 2) {
                Some(data) if k % 2 == 0 => std::borrow::Cow::Borrowed(data.as_slice()),
                _ => std::borrow::Cow::Owned(t.discrete_start(&cx)),
            })
            .collect();
        let discrete: Vec<DiscreteGradient> = physical
            .iter()
            .zip(&starts)
            .map(|(&(term, hessian_factor), data)| DiscreteGradient {
                term,
                start: StepStart {
                    u: u0,
                    data: data.as_ref(),
                    dissipation: chi,
                },
                gradient_factor: 2.0,
                hessian_factor,
            })
            .collect();
        let mut terms: Vec<&dyn Term> = vec![&inertia];
        terms.extend(discrete.iter().map(|t| t as &dyn Term));
        // the doubled equation carries twice the hinge force
        let mut lambda = start.lambda.map(|l| 2.0 * l);
        let weight = m.pendulum_weight();
        let scale = energy_scale(
            start.kinetic,
            weight * m.length_scale(),
            m.applied_torque(t_new, start.held_torque),
        );
        // never below the energy floor: a body that nothing moves (no gravity, no torque, at rest)
        // has a scale of 0, and its balance could only be met exactly
        let energy_bound = m.config.solver.energy_tolerance * scale.max(m.energy_floor());
        let frame_angle = m.projection.angle(&u);
        let settings = NewtonSettings {
            tolerance: m.config.solver.tolerance,
            max_iterations: m.config.solver.max_iterations,
            residual_tolerance: RESIDUAL_TOLERANCE,
            load_scale: 2.0 * start.load_scale,
            length_scale: m.length_scale(),
            frame_angle,
            matrix_key: Self::inertia_factor(dt) / (1.0 + chi),
            reuse: !iterate.fresh_tangent,
            residual_turn: 0.5 * wrap_angle(frame_angle - m.projection.angle(u0)),
        };
        let report = solver.solve(
            &m.pattern,
            &terms,
            &cx,
            &mut u,
            &mut lambda,
            &settings,
            Some((u0, energy_bound)),
            iterate.correct,
        )?;
        Ok(Stepped {
            state: Self::correct(dt, state, u),
            lambda: lambda.map(|l| 0.5 * l),
            iterations: report.iterations,
            factorizations: report.factorizations,
        })
    }

    /// The midpoint rule turns a rigid body along the chord: `tan(Δφ/2) = Δt ω̄ / 2`.
    fn turn(&self, phi: f64) -> f64 {
        2.0 * (0.5 * phi).atan()
    }

    fn uses_elastic_starts(&self) -> bool {
        true
    }

    fn keeps_mean_acceleration(&self) -> bool {
        true
    }

    fn retries_uncorrected(&self) -> bool {
        true
    }

    fn extrapolates_shape(&self) -> bool {
        true
    }
}
