//! A [`Simulation`] of a reduced body (`model.kind = "reduced"`, [`crate::reduced`]): its initial
//! state, its steps, and the full model's fields reconstructed from it (with a wall the head's arc
//! and the block after each step, for the impacts' location; everything else when read), so that
//! the outputs, the impacts' location and the records read the same state as the full model's.
//!
//! The hinge force over a step is the balance of linear momentum of the reduced motion,
//! `F_hinge = (P₁ − P₀)/h − m g − F_wall` \[N\] (`F_wall` the wall's mean force over the step), the
//! full model's multiplier `−λ` of the same step.

use super::{Kinematics, Simulation};
use crate::error::NewtonError;
use crate::reduced::wall::QUASI_STATIC;
use crate::reduced::Loads;

impl Simulation {
    /// The reduced body's initial state (with the current torque input), and the fields.
    pub(super) fn initialize_reduced(&mut self) {
        let Some(body) = &self.model.reduced else {
            return;
        };
        let torque0 = self.model.applied_torque(0.0, self.held_torque);
        let mut r = body.initial_state(&self.model.config, torque0);
        body.fields(&r, &mut self.state.u, &mut self.state.v);
        if let Some(wall) = &self.model.reduced_wall {
            // the block starts at rest, undeformed, as the full model's
            (r.wall_q, r.wall_v) = (vec![0.0; wall.modes()], vec![0.0; wall.modes()]);
            wall.fields(&r.wall_q, &r.wall_v, &mut self.state.u, &mut self.state.v);
        }
        self.reduced = Some(r);
        self.rates = None;
        self.validity = Default::default();
        self.check_validity();
    }

    /// Evaluates the reduced body's error estimate ([`crate::reduced::validity`]) at the current
    /// state, keeping the first warning for [`Simulation::take_warning`].
    fn check_validity(&mut self) {
        let (Some(body), Some(r)) = (&self.model.reduced, &self.reduced) else {
            return;
        };
        let mut eta = body.error_estimate(&self.model, &r.q);
        if let Some(wall) = &self.model.reduced_wall {
            eta = eta.max(wall.error_estimate(&self.model, &r.wall_q));
        }
        if let Some(w) = self.validity.observe(eta, self.state.t, body.strain(&r.q)) {
            self.pending_warning = Some(w.to_string());
        }
    }

    /// With the reduced deformable wall: whether every finished impact lasted at least
    /// [`QUASI_STATIC`] periods of the block's lowest Ritz frequency ([`crate::reduced::wall`]);
    /// warns once otherwise.
    fn check_quasi_static(&mut self) {
        use super::impact::ContactEventKind;
        let Some(wall) = &self.model.reduced_wall else {
            return;
        };
        let period = wall.lowest_period();
        let shortest = self
            .events
            .windows(2)
            .filter(|w| w[0].kind == ContactEventKind::Start && w[1].kind == ContactEventKind::End)
            .map(|w| (w[1].time - w[0].time, w[0].time))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((duration, t)) = shortest.filter(|(d, _)| *d < QUASI_STATIC * period) {
            let message = format!(
                "warning: the reduced deformable wall (model.kind = \"reduced\") does not apply here: the impact at \
                 t = {t:.6} s lasted {duration:.3e} s, {:.1} periods of the block's lowest frequency ({:.4e} Hz), fewer \
                 than {QUASI_STATIC}: its inertia matters and its static modes miss it; use model.kind = \"full\" (or \
                 a stiffer block)",
                duration / period,
                1.0 / period
            );
            if let Some(w) = self.validity.warn(message) {
                self.pending_warning = Some(w.to_string());
            }
        }
    }

    /// The reduced body's largest error estimate so far and when it was reached `(η, t)`
    /// ([`crate::reduced::validity`]); `None` for the full model.
    pub fn error_estimate(&self) -> Option<(f64, f64)> {
        self.validity.largest
    }

    /// The reduced body's fields `[u, v]` of the current state, reconstructed on the first call
    /// after a step; `None` when [`Simulation::state`] holds them.
    pub(super) fn lazy_fields(&self) -> Option<&[Vec<f64>; 2]> {
        let (Some(body), Some(r), true) = (&self.model.reduced, &self.reduced, self.fields_stale) else {
            return None;
        };
        Some(self.lazy_fields.get_or_init(|| {
            let (mut u, mut v) = (vec![0.0; self.state.u.len()], vec![0.0; self.state.v.len()]);
            body.fields(r, &mut u, &mut v);
            if let Some(wall) = &self.model.reduced_wall {
                wall.fields(&r.wall_q, &r.wall_v, &mut u, &mut v);
            }
            [u, v]
        }))
    }

    /// Brings [`Simulation::state`]'s displacement and velocity up to the reduced body's
    /// coordinates, for the readers that take them from there (frames, the acceleration field).
    pub(super) fn sync_fields(&mut self) {
        if let Some([u, v]) = self.lazy_fields().cloned() {
            self.state.u = u;
            self.state.v = v;
        }
        self.fields_stale = false;
    }

    /// A warning the run has raised since the last call (the reduced body's, once, when it does
    /// not apply), for the driver to show.
    pub fn take_warning(&mut self) -> Option<String> {
        self.pending_warning.take()
    }

    /// The reduced body's coordinates and momenta, `None` for the full model.
    pub fn reduced_state(&self) -> Option<&crate::reduced::ReducedState> {
        self.reduced.as_ref()
    }

    /// Advances the reduced body by `h`, halving a step whose Newton iterations fail as
    /// `solver.max_cutbacks` allows (as the full model's steps, [`crate::config::Cutbacks`]);
    /// returns the iterations, or the failure and the shortest step tried.
    pub(super) fn advance_reduced(&mut self, h: f64) -> Result<usize, (NewtonError, f64)> {
        self.advance_reduced_at(h, 0)
    }

    fn advance_reduced_at(&mut self, h: f64, depth: usize) -> Result<usize, (NewtonError, f64)> {
        match self.reduced_step(h) {
            Ok(its) => Ok(its),
            Err((e, _)) => {
                let allowed = self
                    .model
                    .config
                    .solver
                    .max_cutbacks
                    .allows(depth, h, self.model.wave_time());
                if !allowed {
                    return Err((e, h));
                }
                self.cutbacks += 1;
                let a = self.advance_reduced_at(0.5 * h, depth + 1)?;
                let b = self.advance_reduced_at(0.5 * h, depth + 1)?;
                Ok(e.iterations() + a + b)
            }
        }
    }

    /// One step of length `h` of the reduced body; the fields, multipliers and the torque's work
    /// follow. On failure nothing changes.
    fn reduced_step(&mut self, h: f64) -> Result<usize, (NewtonError, f64)> {
        // the impacts ended since the last step, against the block's static basis
        if self.model.reduced_wall.is_some() && self.events.len() != self.validity.events {
            self.validity.events = self.events.len();
            self.check_quasi_static();
        }
        let (Some(body), Some(r0)) = (&self.model.reduced, &self.reduced) else {
            unreachable!("advance_reduced is called for a reduced model")
        };
        let m = &self.model;
        let t0 = self.state.t;
        let torque = 0.5 * (m.applied_torque(t0, self.held_torque) + m.applied_torque(t0 + h, self.held_torque));
        let g = m.config.gravity.g;
        let block = m.reduced_wall.as_deref().zip(m.wall.as_ref());
        let loads = Loads {
            gravity: g,
            torque,
            wall: if block.is_some() { None } else { m.wall.as_ref() },
            block,
        };
        let (r1, report) = body.step(r0, h, &loads).map_err(|e| {
            (
                NewtonError::MaxIterations {
                    iterations: e.iterations,
                    energy_norm: f64::NAN,
                    residual: e.update,
                    forces: 0.0,
                },
                h,
            )
        })?;
        let (p0, p1) = (body.linear_momentum(r0), body.linear_momentum(&r1));
        let f = report.contact_force;
        // F_hinge = ΔP/h − m g − F_wall, g = (0, −g)
        let hinge = [(p1[0] - p0[0]) / h - f[0], (p1[1] - p0[1]) / h + body.mass * g - f[1]];
        self.lambda = [-hinge[0], -hinge[1]];
        self.torque_work += torque * (body.hub_angle(&r1) - body.hub_angle(r0));
        // the impact location reads the fields after every step; without a wall only frames and
        // the accessors do, on demand
        // (the head's arc and the block: the contact's nodes and the block's weight); the rest
        // of the fields is rebuilt when read
        if m.wall.is_some() {
            body.fields_at(&r1, &m.contact_nodes, &mut self.state.u, &mut self.state.v);
            if let Some(wall) = &m.reduced_wall {
                wall.fields(&r1.wall_q, &r1.wall_v, &mut self.state.u, &mut self.state.v);
            }
        }
        self.fields_stale = true;
        self.lazy_fields = Default::default();
        self.state.t = t0 + h;
        self.reduced = Some(r1);
        self.rates = None;
        // the branch of θ for the next (sub)step's context
        self.theta = self.unwrap.next(self.proxy_angle());
        if self
            .validity
            .due(body.strain(&self.reduced.as_ref().expect("just set").q))
        {
            self.check_validity();
        }
        Ok(report.iterations)
    }

    /// A lower bound of the reduced body's distance to the wall in the current state \[m\]
    /// (positive: nothing touches); `None` for the full model or without a wall.
    pub(super) fn reduced_clearance(&self) -> Option<f64> {
        let (Some(body), Some(r), Some(wall)) = (&self.model.reduced, &self.reduced, &self.model.wall) else {
            return None;
        };
        Some(match &self.model.reduced_wall {
            Some(block) => block.clearance(body, r.theta, &r.q, &r.wall_q, wall.face_x),
            None => body.clearance(r.theta, &r.q, wall.face_x),
        })
    }

    /// The proxy angle of the current state, on `(−π, π]` for the full model ([`crate::rigid::RigidProjection`]) and on the frame's branch for a reduced body \[rad\].
    pub(super) fn proxy_angle(&self) -> f64 {
        match (&self.model.reduced, &self.reduced) {
            (Some(body), Some(r)) => body.proxy_angle(r),
            _ => self.model.projection.angle(&self.state.u),
        }
    }

    /// The rigid-body measures of a reduced body's state (see [`crate::reduced::outputs`]),
    /// `None` for the full model.
    pub(super) fn reduced_kinematics(&self) -> Option<Kinematics> {
        let (Some(body), Some(r)) = (&self.model.reduced, &self.reduced) else {
            return None;
        };
        let m = &self.model;
        let torque = m.applied_torque(self.state.t, self.held_torque);
        let rigid = if m.reduced_wall.is_some() {
            None
        } else {
            m.wall.as_ref()
        };
        let (omega, mut alpha) = body.rates(r, m.config.gravity.g, torque, rigid);
        // the deformable wall: its contact's moment on the head, from the fields (kept current
        // after every step with a wall), and the block's kinetic energy
        let mut kinetic = body.kinetic(r);
        if let (Some(wall), Some(contact)) = (&m.reduced_wall, &m.wall) {
            if self.reduced_clearance().is_some_and(|c| c <= 0.0) {
                alpha += wall.contact_moment(contact, &self.state.u) / body.inertia_at(&r.q);
            }
            kinetic += 0.5 * r.wall_v.iter().map(|v| v * v).sum::<f64>();
        }
        Some(Kinematics {
            omega,
            alpha,
            kinetic,
            momentum: body.momenta(r)[0],
            inertia_force: f64::NAN,
        })
    }
}
