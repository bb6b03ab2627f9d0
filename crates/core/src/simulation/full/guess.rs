//! The full body's starting guess of a step: the current configuration turned rigidly about the
//! pivot, with the change of its shape carried on (energy-momentum scheme), or inside a chattering
//! impact the extrapolation of its alternation.
//!
//! **The rigid turn** by `Δφ = ω Δt + ½ α Δt² + ¼ α̇ Δt³` (best-fit rates; `α̇` from the previous
//! step), along the chord for the energy-momentum scheme ([`crate::scheme::TimeScheme::turn`]).
//! Extrapolating displacements linearly instead, `u + Δt v + ½Δt² a`, stretches a rotating body
//! isotropically by `~ω α Δt³`: for steel a spurious stress of megapascals whose geometric
//! stiffness can make the tangent indefinite. The rotation about the pivot keeps the hinge's mean
//! displacement zero (the hinge edge is centred on it).
//!
//! **The shape's change** ([`Full::shape_extrapolation`]): the rigid turn alone leaves the elastic
//! change of a step (the weight's load turning in the body's frame, at the rate `ω`) to Newton;
//! carried on from the last step, the guess's non-rigid error is that change's change, and a
//! smooth swing's steps converge in one iteration.
//!
//! **A chattering contact** ([`Full::chatter_guess`]): where the penalty is far stiffer than the
//! body, the arc's points alternate between entering and leaving the wall from one sub-step to
//! the next (see [`crate::simulation`]'s `impact`). Once the smallest gap has alternated over the
//! last three sub-step ends, the guess takes the state two sub-steps back, moved on by the drift
//! measured over the two sub-steps before (the extrapolation exact for a motion linear in time
//! plus an alternation from one sub-step to the next):
//!
//! ```text
//! u_{n+1} ≈ u_{n−1} + (t_{n+1} − t_{n−1}) / (t_n − t_{n−2}) · (u_n − u_{n−2})
//! ```
//!
//! and the tangent is made afresh (the previous sub-step's factorisation has the entering and
//! leaving points' slopes swapped).

use super::Full;
use crate::model::Model;
use crate::simulation::events::ImpactTrail;
use crate::simulation::interface::Ask;
use crate::simulation::Now;

impl Full {
    /// The rigid turn of the current configuration over a step of `dt`, with the shape's change
    /// carried on where the scheme extrapolates it (see the module doc).
    pub(super) fn rotational_guess(&mut self, model: &Model, now: &mut Now, dt: f64, ask: &Ask) -> Vec<f64> {
        let k = self.kinematics_of(model, now, ask.step);
        let (omega, alpha) = (k.omega, k.alpha);
        // Newmark-consistent: Δφ = ω Δt + Δt²/4 (α_n + α_{n+1}) with α_{n+1} ≈ α_n + α̇ Δt,
        // α̇ from the previous step.
        let jerk = match self.previous_alpha {
            Some((t_prev, a_prev)) if now.state.t > t_prev => (alpha - a_prev) / (now.state.t - t_prev),
            _ => 0.0,
        };
        // Δt ω̄ with the mean rate ω̄ = ω + ½ α Δt + ¼ α̇ Δt² of the step
        let phi = self
            .scheme
            .turn(omega * dt + 0.5 * alpha * dt * dt + 0.25 * jerk * dt * dt * dt);
        let shaped = self.shape_extrapolation(model, now, dt, ask);
        let u = &now.state.u;
        let mut guess = u.clone();
        // the pendulum turns; the other bodies start from where they are
        let pendulum = 0..model.bodies[0].nodes.end;
        crate::rigid::turn_about_pivot(
            &model.mesh.nodes,
            shaped.as_deref().unwrap_or(u),
            &mut guess,
            pendulum,
            phi,
        );
        guess
    }

    /// The current displacement with the change of the pendulum's shape over the last step
    /// extrapolated by `Δt` (`None` for a scheme that does not extrapolate, before the first
    /// step, when the last step was shorter than half of `Δt`, and after a step that took more
    /// than one Newton iteration).
    ///
    /// The midpoint rule's `u₁ − u₀ = h (v₀ + v₁)/2` with the step's mean acceleration
    /// `a₁ = (v₁ − v₀)/h` gives back the start of the last step from the current state exactly:
    /// `u₀ = u₁ − h v₁ + ½ h² a₁` (`h` the last step's length). Its positions `x₀ = X + u₀`
    /// turned about the pivot by the change `Δθ` of the proxy angle over that step are the last
    /// state seen in the current frame; `x₁ − Q(Δθ) x₀` is the shape's change over the step
    /// without its rotation, and
    ///
    /// ```text
    /// x̃ = x₁ + (Δt / h) (x₁ − Q(Δθ) x₀)
    /// ```
    ///
    /// the shape extrapolated linearly in the body's frame; the caller turns it by the step's
    /// predicted rotation. The nodal velocity is no substitute for the difference: the midpoint
    /// rule's end velocity `v₁ = 2 (u₁ − u₀)/h − v₀` of a turning body alternates, step to step,
    /// by a radial part of `~ω² h r`, several times the shape's change, while the positions'
    /// chord does not. The other bodies (a wall) keep their displacement.
    ///
    /// The extrapolation is made only after a step that converged in one iteration: its shape
    /// changed smoothly at the scale of the step. Where the step does not resolve the elastic
    /// motion (the ringing after an impact at a long step) the shape's change alternates from
    /// step to step, and extrapolating it costs iterations instead of saving them.
    fn shape_extrapolation(&self, model: &Model, now: &Now, dt: f64, ask: &Ask) -> Option<Vec<f64>> {
        if !self.scheme.extrapolates_shape() || ask.step == 0 || ask.last_iterations > 1 {
            return None;
        }
        let (t_prev, _) = self.previous_alpha?;
        let h = now.state.t - t_prev;
        // a last step much shorter than this one (a cut-back, an impact's sub-step) is a poor
        // base for a long extrapolation: the rigid turn alone then
        if !(h > 0.0 && dt <= 2.0 * h) {
            return None;
        }
        let m = model;
        let (u, v, a) = (&now.state.u, &now.state.v, &now.state.a);
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

    /// The guess of a sub-step of length `dt` inside a chattering impact (see the module doc),
    /// or `None`: fewer than three sub-steps of the impact behind the current state, or a
    /// smallest gap that did not alternate over them.
    pub(super) fn chatter_guess(&self, model: &Model, now: &Now, trail: &ImpactTrail, dt: f64) -> Option<Vec<f64>> {
        let wall = model.wall.as_ref()?;
        let [(t2, u2), (t1, u1)] = trail.earlier.as_slice() else {
            return None;
        };
        let (t0, u0) = (now.state.t, &now.state.u);
        if trail.end != t0 {
            return None;
        }
        let [g2, g1, g0] = [u2, u1, u0].map(|u| wall.smallest_gap(u));
        if (g0 - g1) * (g1 - g2) >= 0.0 {
            return None;
        }
        let drift = (t0 + dt - t1) / (t0 - t2);
        Some(
            u1.iter()
                .zip(u0)
                .zip(u2)
                .map(|((a, b), c)| a + drift * (b - c))
                .collect(),
        )
    }
}
