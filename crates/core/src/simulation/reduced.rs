//! The reduced body as the stepper's body (`model.kind = "reduced"`, [`crate::reduced`]): built
//! from the full model's operators (or read from the cache), its steps in its own coordinates,
//! and the full model's fields rebuilt from them (with a wall the head's arc and the block after
//! each step, for the impacts' location; everything else when read), so that the outputs, the
//! impacts' location and the records read the same state as the full body's.
//!
//! The hinge force over a step is the balance of linear momentum of the reduced motion,
//! `F_hinge = (P₁ − P₀)/h − m g − F_wall` \[N\] (`F_wall` the wall's mean force over the step), the
//! full model's multiplier `−λ` of the same step.
//!
//! Beside a deformable wall the pendulum's basis is that of the pendulum alone with a rigid face
//! where the block's is (its contact modes and touch points), built from a model of the pendulum
//! alone; the block is reduced beside it ([`ReducedWall`]).

use std::sync::{Arc, OnceLock};

use super::events::{ContactEvent, ContactEventKind};
use super::interface::{Ask, BodySnapshot, Taken};
use super::measures::Kinematics;
use super::Now;
use crate::config::{Config, ModelKind, TorqueProfile, WallKind};
use crate::error::Error;
use crate::error::NewtonError;
use crate::mesh::Mesh;
use crate::model::{Fingerprint, Model, CONTACT_BOUNDARY};
use crate::post::NodalStress;
use crate::reduced::outputs::StressReference;
use crate::reduced::wall::QUASI_STATIC;
use crate::reduced::{cache, Loads, ReducedBody, ReducedState, ReducedWall, Validity};

/// A reduced body read from the cache while the model's operators were built.
pub(crate) type Stored = Arc<ReducedBody>;

/// The reduced body of a simulation (see the module doc).
pub(crate) struct Reduced {
    /// The body's operators.
    body: Arc<ReducedBody>,
    /// The deformable wall reduced beside it, if the model has one.
    wall: Option<Arc<ReducedWall>>,
    /// The body's cache file while it is written beside the run (a body computed, not read):
    /// waited for when dropped ([`cache::build_and_keep`]).
    _cache_write: cache::PendingWrite,
    /// The nodes of the head's arc with a wall, none without: all of the pendulum's fields it
    /// rebuilds after each step (the contact reads them).
    contact_nodes: Vec<usize>,
    /// Coordinates and momenta.
    state: ReducedState,
    /// The error estimate so far ([`crate::reduced::validity`]).
    validity: Validity,
    /// The last fully evaluated stress state, for the largest von Mises stress.
    stress_reference: StressReference,
    /// Whether the fields in `Now` lag the coordinates (rebuilt only when read).
    fields_stale: bool,
    /// The fields `[u, v]`, rebuilt on the first read after a step.
    lazy_fields: OnceLock<[Vec<f64>; 2]>,
    /// A warning not yet taken.
    warning: Option<String>,
}

impl Reduced {
    /// The reduced body of `config` from the cache, looked up while the model is built (not
    /// beside a deformable wall, whose body comes from a model of the pendulum alone).
    pub fn prepare(config: &Config, fingerprint: &Fingerprint) -> Option<Stored> {
        if config.wall.kind == WallKind::Deformable {
            return None;
        }
        let torque = config.torque.profile != TorqueProfile::None;
        let stored = cache::stored(cache::key_of(config, fingerprint.mesh, torque));
        stored.inspect(|body| body.stress.prepare())
    }

    /// The reduced body of `model`: `stored` if the cache had it, else computed (and kept).
    pub fn new(model: &Model, stored: Option<Stored>) -> Result<Self, Error> {
        let config = &model.config;
        let (body, wall, write) = if config.wall.kind == WallKind::Deformable {
            let mut c = config.clone();
            (c.model.kind, c.wall.kind) = (ModelKind::Full, WallKind::Rigid);
            let twin = Model::new(&c, pendulum_mesh(model))?;
            let (body, write) = cache::load_or_build(&twin, || crate::reduced::basis::for_model(&twin))?;
            let wall = ReducedWall::build(model, &body, config.model.contact_modes)?;
            (body, Some(Arc::new(wall)), write)
        } else {
            match stored {
                Some(body) => (body, None, cache::PendingWrite::default()),
                None => {
                    let (body, write) =
                        cache::build_and_keep(cache::key(model), || crate::reduced::basis::for_model(model))?;
                    (body, None, write)
                }
            }
        };
        let contact_nodes = match config.wall.is_present() {
            true => model.bodies[0].mesh.nodes_on(CONTACT_BOUNDARY),
            false => Vec::new(),
        };
        // set by `initialize`
        let state = ReducedState {
            theta: 0.0,
            q: Vec::new(),
            v: Vec::new(),
            wall_q: Vec::new(),
            wall_v: Vec::new(),
            jacobian: None,
        };
        Ok(Self {
            body,
            wall,
            _cache_write: write,
            contact_nodes,
            state,
            validity: Validity::default(),
            stress_reference: StressReference::default(),
            fields_stale: false,
            lazy_fields: OnceLock::new(),
            warning: None,
        })
    }

    /// The initial state (with the current torque input) and its fields.
    pub fn initialize(&mut self, model: &Model, now: &mut Now) {
        let torque0 = model.applied_torque(0.0, now.held_torque);
        let mut r = self.body.initial_state(&model.config, torque0);
        self.body.fields(&r, &mut now.state.u, &mut now.state.v);
        if let Some(wall) = &self.wall {
            // the block starts at rest, undeformed, as the full model's
            (r.wall_q, r.wall_v) = (vec![0.0; wall.modes()], vec![0.0; wall.modes()]);
            wall.fields(&r.wall_q, &r.wall_v, &mut now.state.u, &mut now.state.v);
        }
        self.state = r;
        self.fields_stale = false;
        self.lazy_fields = OnceLock::new();
        now.forget_measures();
        self.validity = Validity::default();
        self.check_validity(model, now.state.t);
    }

    /// Evaluates the error estimate ([`crate::reduced::validity`]) at the current state, keeping
    /// the first warning.
    fn check_validity(&mut self, model: &Model, t: f64) {
        let r = &self.state;
        let mut eta = self.body.error_estimate(model, &r.q);
        if let Some(wall) = &self.wall {
            eta = eta.max(wall.error_estimate(model, &r.wall_q));
        }
        if let Some(w) = self.validity.observe(eta, t, self.body.strain(&r.q)) {
            self.warning = Some(w.to_string());
        }
    }

    /// With the reduced deformable wall: whether every finished impact of `events` lasted at least
    /// [`QUASI_STATIC`] periods of the block's lowest Ritz frequency ([`crate::reduced::wall`]);
    /// warns once otherwise.
    fn check_quasi_static(&mut self, events: &[ContactEvent]) {
        let Some(wall) = &self.wall else {
            return;
        };
        let period = wall.lowest_period();
        let shortest = events
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
                self.warning = Some(w.to_string());
            }
        }
    }

    /// The largest error estimate so far and when it was reached `(η, t)`.
    pub fn error_estimate(&self) -> Option<(f64, f64)> {
        self.validity.largest
    }

    /// A warning raised since the last call.
    pub fn take_warning(&mut self) -> Option<String> {
        self.warning.take()
    }

    /// Coordinates and momenta.
    pub fn state(&self) -> &ReducedState {
        &self.state
    }

    /// The fields `[u, v]` of the current state: rebuilt on the first call after a step, or those
    /// of `now` where they are current.
    pub fn fields<'a>(&'a self, now: &'a Now) -> [&'a [f64]; 2] {
        if !self.fields_stale {
            return [&now.state.u, &now.state.v];
        }
        let [u, v] = self.lazy_fields.get_or_init(|| {
            let (mut u, mut v) = (vec![0.0; now.state.u.len()], vec![0.0; now.state.v.len()]);
            self.body.fields(&self.state, &mut u, &mut v);
            if let Some(wall) = &self.wall {
                wall.fields(&self.state.wall_q, &self.state.wall_v, &mut u, &mut v);
            }
            [u, v]
        });
        [u, v]
    }

    /// Brings the fields of `now` up to the coordinates.
    pub fn sync_fields(&mut self, now: &mut Now) {
        if self.fields_stale {
            let [u, v] = self.fields(now).map(<[f64]>::to_vec);
            (now.state.u, now.state.v) = (u, v);
        }
        self.fields_stale = false;
    }

    /// One step of length `h`; the fields, multipliers and the torque's work follow. On failure
    /// nothing changes.
    pub fn step(&mut self, model: &Model, now: &mut Now, h: f64, ask: &Ask) -> Result<Taken, NewtonError> {
        // the impacts ended since the last step, against the block's static basis
        if self.wall.is_some() && ask.events.len() != self.validity.events {
            self.validity.events = ask.events.len();
            self.check_quasi_static(ask.events);
        }
        let (body, r0, m) = (&self.body, &self.state, model);
        let t0 = now.state.t;
        let torque = 0.5 * (m.applied_torque(t0, now.held_torque) + m.applied_torque(t0 + h, now.held_torque));
        let g = m.config.gravity.g;
        let block = self.wall.as_deref().zip(m.wall.as_ref());
        let loads = Loads {
            gravity: g,
            torque,
            wall: if block.is_some() { None } else { m.wall.as_ref() },
            block,
        };
        let (r1, report) = body.step(r0, h, &loads).map_err(|e| NewtonError::MaxIterations {
            iterations: e.iterations,
            energy_norm: f64::NAN,
            residual: e.update,
            forces: 0.0,
        })?;
        let (p0, p1) = (body.linear_momentum(r0), body.linear_momentum(&r1));
        let f = report.contact_force;
        // F_hinge = ΔP/h − m g − F_wall, g = (0, −g)
        let hinge = [(p1[0] - p0[0]) / h - f[0], (p1[1] - p0[1]) / h + body.mass * g - f[1]];
        now.lambda = [-hinge[0], -hinge[1]];
        now.torque_work += torque * (body.hub_angle(&r1) - body.hub_angle(r0));
        // the impact location reads the fields after every step (the head's arc and the block:
        // the contact's nodes and the block's weight); without a wall only frames and the
        // accessors do, on demand; the rest of the fields is rebuilt when read
        if m.wall.is_some() {
            body.fields_at(&r1, &self.contact_nodes, &mut now.state.u, &mut now.state.v);
            if let Some(wall) = &self.wall {
                wall.fields(&r1.wall_q, &r1.wall_v, &mut now.state.u, &mut now.state.v);
            }
        }
        self.fields_stale = true;
        self.lazy_fields = OnceLock::new();
        now.state.t = t0 + h;
        self.state = r1;
        now.forget_measures();
        // the branch of θ for the next (sub)step's context
        now.theta = now.unwrap.next(self.body.proxy_angle(&self.state));
        if self.validity.due(self.body.strain(&self.state.q)) {
            self.check_validity(model, now.state.t);
        }
        Ok(Taken {
            iterations: report.iterations,
            factorizations: 0,
        })
    }

    /// A lower bound of the distance to the wall \[m\] (positive: nothing touches); `None`
    /// without a wall.
    pub fn clearance(&self, model: &Model) -> Option<f64> {
        let contact = model.wall.as_ref()?;
        let r = &self.state;
        Some(match &self.wall {
            Some(block) => block.clearance(&self.body, r.theta, &r.q, &r.wall_q, contact.face_x),
            None => self.body.clearance(r.theta, &r.q, contact.face_x),
        })
    }

    /// The proxy angle of the current state, on the frame's branch \[rad\].
    pub fn proxy_angle(&self) -> f64 {
        self.body.proxy_angle(&self.state)
    }

    /// The rigid-body measures of the current state ([`crate::reduced::outputs`]).
    pub fn kinematics(&self, model: &Model, now: &Now) -> Kinematics {
        let (body, r, m) = (&self.body, &self.state, model);
        let torque = m.applied_torque(now.state.t, now.held_torque);
        let rigid = if self.wall.is_some() { None } else { m.wall.as_ref() };
        let (omega, mut alpha) = body.rates(r, m.config.gravity.g, torque, rigid);
        // the deformable wall: its contact's moment on the head, from the fields (kept current
        // after every step with a wall), and the block's kinetic energy
        let mut kinetic = body.kinetic(r);
        if let (Some(wall), Some(contact)) = (&self.wall, &m.wall) {
            if self.clearance(model).is_some_and(|c| c <= 0.0) {
                alpha += wall.contact_moment(contact, &now.state.u) / body.inertia_at(&r.q);
            }
            kinetic += 0.5 * r.wall_v.iter().map(|v| v * v).sum::<f64>();
        }
        Kinematics {
            omega,
            alpha,
            kinetic,
            momentum: body.momenta(r)[0],
            inertia_force: f64::NAN,
        }
    }

    /// `[strain, gravity, contact]` energy of the current state \[J\].
    pub fn energies(&self, model: &Model, now: &Now) -> [f64; 3] {
        let (body, r, m) = (&self.body, &self.state, model);
        match &self.wall {
            // the deformable wall: the block's modal strain energy, its weight and the contact
            // from the fields, which every step with a wall brings up to date
            Some(wall) => {
                let cx = now.context();
                let block_weight = crate::terms::Term::energy(&*m.bodies[1].gravity, &now.state.u, &cx);
                let contact = match self.clearance(model).is_some_and(|c| c > 0.0) {
                    true => 0.0,
                    false => m.contact_energy(&now.state.u, &cx),
                };
                [
                    body.strain(&r.q) + wall.strain(&r.wall_q),
                    body.gravity(r, m.config.gravity.g) + block_weight,
                    contact,
                ]
            }
            None => [
                body.strain(&r.q),
                body.gravity(r, m.config.gravity.g),
                m.wall.as_ref().map_or(0.0, |w| body.contact(r, w).0),
            ],
        }
    }

    /// The gap to the wall \[m\]: from the coordinates against the rigid wall, from the fields
    /// otherwise.
    pub fn gap(&self, model: &Model, now: &Now) -> f64 {
        match (&model.wall, &self.wall) {
            (Some(wall), None) => self.body.contact(&self.state, wall).1,
            _ => super::measures::gap_of_fields(model, &now.state.u),
        }
    }

    /// The wall's normal force on the head \[N\].
    pub fn contact_force(&self, model: &Model, now: &Now) -> f64 {
        if let (Some(wall), None) = (&model.wall, &self.wall) {
            return crate::post::unsigned_zero(self.body.contact(&self.state, wall).2);
        }
        if self.clearance(model).is_some_and(|c| c > 0.0) {
            return 0.0;
        }
        super::measures::contact_force_of_fields(model, &now.state.u)
    }

    /// Nodal stresses of the current state.
    pub fn nodal_stress(&self) -> NodalStress {
        self.body.nodal_stress(&self.state)
    }

    /// The largest nodal von Mises stress of the current state \[Pa\].
    pub fn von_mises_max(&mut self) -> f64 {
        self.body.von_mises_max(&self.state, &mut self.stress_reference)
    }

    /// The body's part of a snapshot: its coordinates and momenta.
    pub fn save(&self) -> BodySnapshot {
        BodySnapshot {
            previous_alpha: None,
            factor: None,
            reduced: Some(self.state.clone()),
        }
    }

    /// Returns to a snapshot's part. The snapshot holds at most the fields the steps read (none
    /// without a wall, the head's arc and the block with one); the rest is rebuilt from the
    /// coordinates.
    pub fn restore(&mut self, s: &BodySnapshot) {
        if let Some(r) = &s.reduced {
            self.state = r.clone();
        }
        self.fields_stale = true;
        self.lazy_fields = OnceLock::new();
    }
}

/// The pendulum's own mesh inside a model's (the pendulum's nodes, elements and boundary edges
/// come first, [`crate::model::body`]): the mesh a model of the pendulum alone is built on.
/// Vertices are numbered before the elements' mid-edge nodes, so the pendulum's vertices are
/// those up to its largest corner.
fn pendulum_mesh(model: &Model) -> Mesh {
    let view = &model.bodies[0].mesh;
    let nodes = model.bodies[0].nodes.clone();
    let corners = view.triangles.iter().flat_map(|t| t[..3].iter().copied()).max();
    Mesh {
        nodes: model.mesh.nodes[nodes].to_vec(),
        num_vertices: corners.map_or(0, |c| c + 1),
        triangles: view.triangles.clone(),
        boundary_edges: view.boundary_edges.clone(),
        boundary_names: view.boundary_names.clone(),
        region_name: view.region_name.clone(),
        order: view.order,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pendulum_part_of_a_model_with_a_block_is_the_pendulum_mesh() {
        let mut cfg = Config::default();
        cfg.wall.kind = WallKind::Deformable;
        let mesh = crate::mesh::generate(&cfg).unwrap();
        let model = Model::new(&cfg, mesh.clone()).unwrap();
        assert!(
            model.mesh.num_nodes() > mesh.num_nodes(),
            "the block's nodes are appended"
        );
        let part = pendulum_mesh(&model);
        assert_eq!(part.nodes, mesh.nodes);
        assert_eq!(part.triangles, mesh.triangles);
        assert_eq!(part.boundary_edges, mesh.boundary_edges);
        assert_eq!(part.num_vertices, mesh.num_vertices);
        assert_eq!(part.region_name, mesh.region_name);
        assert_eq!(part.boundary_names[..mesh.boundary_names.len()], mesh.boundary_names);
        let [a, b] = [&part, &mesh].map(|m| crate::model::fingerprint(&cfg, m, None).mesh);
        assert_eq!(a, b, "the same mesh fingerprint, so the same cache key");
    }
}
