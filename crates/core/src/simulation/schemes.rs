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
    ///
    /// The energy-momentum scheme's guess also carries the change of the body's shape on
    /// ([`Simulation::shape_extrapolation`]): the rigid turn alone leaves the elastic change of a step
    /// (the weight's load turning in the body's frame, at the rate `ω`) to Newton, 3e-10 m per
    /// step of 1 ms in the tutorial's swing, and its first iteration then missed the energy
    /// balance in 70 % of the steps; with the shape extrapolated the guess's non-rigid error is
    /// 2e-12 m and every step converges in one iteration.
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
        let shaped = self.shape_extrapolation(dt);
        let u = &self.state.u;
        let mut guess = u.clone();
        // the pendulum turns; the other bodies start from where they are
        let pendulum = 0..self.model.bodies[0].nodes.end;
        crate::rigid::turn_about_pivot(
            &self.model.mesh.nodes,
            shaped.as_deref().unwrap_or(u),
            &mut guess,
            pendulum,
            phi,
        );
        guess
    }

    /// The current displacement with the change of the pendulum's shape over the last step
    /// extrapolated by `Δt` (energy-momentum scheme; `None` before the first step, for the other
    /// schemes, when the last step was shorter than half of `Δt`, and after a step that took more
    /// than one Newton iteration).
    ///
    /// The midpoint rule's `u₁ − u₀ = h (v₀ + v₁)/2` with the step's mean acceleration
    /// `a₁ = (v₁ − v₀)/h` gives back the start of the last step from the current state exactly:
    /// `u₀ = u₁ − h v₁ + ½ h² a₁` (`h` the last step's length). Its positions `x₀ = X + u₀`
    /// turned about the pivot by the change `Δθ` of the proxy angle over that step are the last
    /// state seen in the current frame; `x₁ − Q(Δθ) x₀` is the shape's change over the step
    /// without its rotation (of the size of the elastic deformation's change, `~1e-10 m` per
    /// millisecond in the tutorial's swing), and
    ///
    /// ```text
    /// x̃ = x₁ + (Δt / h) (x₁ − Q(Δθ) x₀)
    /// ```
    ///
    /// the shape extrapolated linearly in the body's frame; the caller turns it by the step's
    /// predicted rotation. The nodal velocity is no substitute for the difference: the midpoint
    /// rule's end velocity `v₁ = 2 (u₁ − u₀)/h − v₀` of a turning body alternates, step to step,
    /// by a radial part of `~ω² h r`, four times the shape's change (measured), while the
    /// positions' chord does not. The other bodies (a wall) keep their displacement.
    ///
    /// The extrapolation is made only after a step that converged in one iteration: its shape
    /// changed smoothly at the scale of the step. Where the step does not resolve the elastic
    /// motion (the ringing after an impact at `Δt = 10 ms`, three iterations a step) the shape's
    /// change alternates from step to step, and extrapolating it cost a fourth iteration in
    /// those steps (4 % more iterations in the rigid-wall run, 6 % with a torque).
    fn shape_extrapolation(&self, dt: f64) -> Option<Vec<f64>> {
        if self.model.scheme != Scheme::EnergyMomentum || self.step == 0 || self.last_iterations > 1 {
            return None;
        }
        let (t_prev, _) = self.previous_alpha?;
        let h = self.state.t - t_prev;
        // a last step much shorter than this one (a cut-back, an impact's sub-step) is a poor
        // base for a long extrapolation: the rigid turn alone then
        if !(h > 0.0 && dt <= 2.0 * h) {
            return None;
        }
        let m = &self.model;
        let (u, v, a) = (&self.state.u, &self.state.v, &self.state.a);
        let pendulum = 0..m.bodies[0].nodes.end;
        let before: Vec<f64> = (0..u.len()).map(|i| u[i] - h * v[i] + 0.5 * h * h * a[i]).collect();
        let turn = crate::rigid::wrap_angle(m.projection.angle(u) - m.projection.angle(&before));
        // the positions seen before, turned, node by node into the difference
        let turn = turn.sin_cos();
        let ratio = dt / h;
        let mut shaped = u.clone();
        for n in pendulum {
            let seen = crate::rigid::turned(m.mesh.nodes[n], [before[2 * n], before[2 * n + 1]], turn);
            for k in 0..2 {
                let i = 2 * n + k;
                shaped[i] += ratio * (u[i] - seen[k]);
            }
        }
        Some(shaped)
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
        self.elastic_starts();
        let elastic_starts = &self.starts.as_ref().expect("made by elastic_starts").1;
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
        // the bodies' terms come first, each body's elastic term before its weight
        // (`Model::body_terms`); the elastic ones start from the data made for this state
        let starts: Vec<std::borrow::Cow<[f64]>> = physical
            .iter()
            .enumerate()
            .map(|(k, (t, _))| match elastic_starts.get(k / 2) {
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
        let mut lambda = self.lambda.map(|l| 2.0 * l);
        let weight = m.pendulum_weight();
        let scale = crate::energy_momentum::energy_scale(
            kinetic,
            weight * m.length_scale(),
            m.applied_torque(t_new, self.held_torque),
        );
        // never below the energy floor: a body that nothing moves (no gravity, no torque, at rest)
        // has a scale of 0, and its balance could only be met exactly
        let energy_bound = m.config.solver.energy_tolerance * scale.max(m.energy_floor());
        let frame_angle = m.projection.angle(&u);
        let settings = NewtonSettings {
            tolerance: m.config.solver.tolerance,
            max_iterations: m.config.solver.max_iterations,
            residual_tolerance: RESIDUAL_TOLERANCE,
            load_scale: 2.0 * load_scale,
            length_scale: m.length_scale(),
            frame_angle,
            matrix_key: EnergyMomentum::inertia_factor(dt) / (1.0 + chi),
            reuse: !fresh_tangent,
            residual_turn: 0.5 * crate::rigid::wrap_angle(frame_angle - m.projection.angle(u0)),
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
