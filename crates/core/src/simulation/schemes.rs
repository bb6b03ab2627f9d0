//! One step of each time scheme from the current state, not yet taken: the energy-momentum step
//! ([`crate::energy_momentum`]) and the Newmark / HHT-α step ([`crate::newmark`]), both solved by
//! Newton ([`crate::newton`]) from the rigid rotation of the current state.

use super::{Simulation, RESIDUAL_TOLERANCE};
use crate::config::Scheme;
use crate::energy_momentum::EnergyMomentum;
use crate::error::NewtonError;
use crate::newmark::State;
use crate::newton::NewtonSettings;
use crate::terms::{DiscreteGradient, Inertia, Linear, Scaled, StepContext, StepStart, Term};

impl Simulation {
    /// Starting guess of a step: the current configuration rotated rigidly about the pivot by
    /// `Δφ = ω Δt + ½ α Δt² + ¼ α̇ Δt³` (best-fit rates; `α̇` from the previous step). Extrapolating displacements linearly instead,
    /// `u + Δt v + ½Δt² a`, stretches a rotating body isotropically by `~ω α Δt³`: for steel a spurious
    /// stress of megapascals whose geometric stiffness can make the tangent indefinite. The rotation
    /// about the pivot keeps the hinge's mean displacement zero (the hinge edge is centred on it).
    pub(super) fn rotational_guess(&mut self, dt: f64) -> Vec<f64> {
        let (omega, alpha) = self.angular_rates();
        // Newmark-consistent: Δφ = ω Δt + Δt²/4 (α_n + α_{n+1}) with α_{n+1} ≈ α_n + α̇ Δt,
        // α̇ from the previous step.
        let jerk = match self.previous_alpha {
            Some((t_prev, a_prev)) if self.state.t > t_prev => (alpha - a_prev) / (self.state.t - t_prev),
            _ => 0.0,
        };
        // Δt ω̄ with the mean rate ω̄ = ω + ½ α Δt + ¼ α̇ Δt² of the step
        let mut phi = omega * dt + 0.5 * alpha * dt * dt + 0.25 * jerk * dt * dt * dt;
        if self.model.scheme == Scheme::EnergyMomentum {
            // the midpoint rule turns a rigid body along the chord: tan(Δφ/2) = Δt ω̄ / 2
            phi = 2.0 * (0.5 * phi).atan();
        }
        let u = &self.state.u;
        let mut guess = u.clone();
        // the pendulum turns; the other bodies start from where they are
        let pendulum = 0..self.model.bodies[0].nodes.end;
        crate::post::turn_about_pivot(&self.model.mesh.nodes, u, &mut guess, pendulum, phi);
        guess
    }

    /// One energy-momentum step ([`crate::energy_momentum`]); `correct`: whether Newton may
    /// correct slow iterations by GMRES ([`Solver::solve`]).
    fn try_step_energy_momentum(&mut self, dt: f64, correct: bool) -> Result<(State, [f64; 2], usize), NewtonError> {
        // inside a chattering impact, the extrapolation of its alternation, with a fresh tangent;
        // not where it would invert an element (a soft head crushed against the wall, after a
        // cut-back), where the rigid turn of the current state serves
        let chatter = self.chatter_guess(dt).filter(|guess| {
            let cx = StepContext::at(guess, self.state.t + dt, self.theta, self.held_torque);
            self.model.strain_energy(guess, &cx).is_finite()
        });
        let fresh_tangent = chatter.is_some();
        let mut u = chatter.unwrap_or_else(|| self.rotational_guess(dt));
        let (t0, t_new) = (self.state.t, self.state.t + dt);
        let load_scale = self.load_scale(t_new);
        let kinetic = self.kinematics().kinetic;
        let m = &self.model;
        let u0 = &self.state.u;
        let cx = StepContext {
            t: t_new,
            t0,
            dt,
            u0,
            theta0: self.theta,
            torque: self.held_torque,
        };
        let chi = m.config.time.dissipation;
        let inertia = Inertia {
            mass: &m.mass,
            pattern: &m.pattern,
            factor: EnergyMomentum::inertia_factor(dt),
            predictor: EnergyMomentum::predictor(dt, &self.state),
        };
        let mut physical: Vec<(&dyn Term, f64)> = m.body_terms(chi);
        physical.extend(m.loads().map(|t| (t, 1.0)));
        let starts: Vec<Vec<f64>> = physical.iter().map(|(t, _)| t.discrete_start(&cx)).collect();
        let discrete: Vec<DiscreteGradient> = physical
            .iter()
            .zip(&starts)
            .map(|(&(term, hessian_factor), data)| DiscreteGradient {
                term,
                start: StepStart {
                    u: u0,
                    data,
                    dissipation: chi,
                },
                gradient_factor: 2.0,
                hessian_factor,
            })
            .collect();
        let mut terms: Vec<&dyn Term> = vec![&inertia];
        terms.extend(discrete.iter().map(|t| t as &dyn Term));
        // the doubled equation carries twice the hinge force
        let mut lambda = self.lambda.map(|l| 2.0 * l);
        let weight = m.bodies[0].gravity.load_gradient.iter().sum::<f64>();
        let scale = crate::energy_momentum::energy_scale(
            kinetic,
            weight * m.length_scale(),
            m.applied_torque(t_new, self.held_torque),
        );
        // never below the energy floor: a body that nothing moves (no gravity, no torque, at rest)
        // has a scale of 0, and its balance could only be met exactly
        let energy_bound = m.config.solver.energy_tolerance * scale.max(m.energy_floor());
        let settings = NewtonSettings {
            tolerance: m.config.solver.tolerance,
            max_iterations: m.config.solver.max_iterations,
            residual_tolerance: RESIDUAL_TOLERANCE,
            load_scale: 2.0 * load_scale,
            length_scale: m.length_scale(),
            frame_angle: m.projection.angle(&u),
            matrix_key: EnergyMomentum::inertia_factor(dt) / (1.0 + chi),
            reuse: !fresh_tangent,
            residual_turn: 0.5 * crate::newton::wrap_angle(m.projection.angle(&u) - m.projection.angle(u0)),
        };
        let report = self.solver.solve(
            &m.pattern,
            &terms,
            &cx,
            &mut u,
            &mut lambda,
            &settings,
            Some((u0, energy_bound)),
            correct,
        )?;
        let new_state = EnergyMomentum::correct(dt, &self.state, u);
        self.total_factorizations += report.factorizations;
        Ok((new_state, lambda.map(|l| 0.5 * l), report.iterations))
    }

    /// One step of length `dt` from the current state (not taken: the new state, the hinge
    /// multipliers and the Newton iterations); `correct` as in [`Simulation::try_step_energy_momentum`]
    /// (the Newmark schemes minimise and never correct).
    pub(super) fn try_step(&mut self, dt: f64, correct: bool) -> Result<(State, [f64; 2], usize), NewtonError> {
        if self.model.scheme == Scheme::EnergyMomentum {
            return self.try_step_energy_momentum(dt, correct);
        }
        let mut u = self.rotational_guess(dt);
        let t_new = self.state.t + dt;
        let load_scale = self.load_scale(t_new);
        let m = &self.model;
        let cx = StepContext {
            t: t_new,
            t0: self.state.t,
            dt,
            u0: &self.state.u,
            theta0: self.theta,
            torque: self.held_torque,
        };
        let inertia = Inertia {
            mass: &m.mass,
            pattern: &m.pattern,
            factor: m.newmark.inertia_factor(dt),
            predictor: m.newmark.predict_u(dt, &self.state),
        };
        let mut physical: Vec<&dyn Term> = m.body_terms(0.0).into_iter().map(|(t, _)| t).collect();
        physical.extend(m.loads());
        // HHT-α: (1 + α) Π(u, tₙ₊₁) − α ∇Π(uₙ, tₙ)·u; plain terms for the trapezoidal rule.
        let alpha = m.hht_alpha;
        let scaled: Vec<Scaled> = physical
            .iter()
            .map(|&term| Scaled {
                term,
                factor: 1.0 + alpha,
            })
            .collect();
        let mut previous = Linear { gradient: Vec::new() };
        let mut terms: Vec<&dyn Term> = vec![&inertia];
        if alpha == 0.0 {
            terms.extend(physical.iter().copied());
        } else {
            previous.gradient = vec![0.0; self.state.u.len()];
            let start = StepContext::at(&self.state.u, self.state.t, self.theta, self.held_torque);
            for term in &physical {
                term.add_gradient(&self.state.u, &start, &mut previous.gradient);
            }
            previous.gradient.iter_mut().for_each(|g| *g *= -alpha);
            terms.extend(scaled.iter().map(|t| t as &dyn Term));
            terms.push(&previous);
        }
        let mut lambda = self.lambda;
        let settings = NewtonSettings {
            tolerance: m.config.solver.tolerance,
            max_iterations: m.config.solver.max_iterations,
            residual_tolerance: RESIDUAL_TOLERANCE,
            load_scale,
            length_scale: m.length_scale(),
            frame_angle: m.projection.angle(&u),
            matrix_key: m.newmark.inertia_factor(dt) / (1.0 + alpha),
            reuse: true,
            residual_turn: 0.0,
        };
        let report = self
            .solver
            .minimize(&m.pattern, &terms, &cx, &mut u, &mut lambda, &settings)?;
        let new_state = m.newmark.correct(dt, &self.state, u);
        self.total_factorizations += report.factorizations;
        Ok((new_state, lambda, report.iterations))
    }
}
