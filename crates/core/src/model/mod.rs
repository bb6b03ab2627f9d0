//! The [`Model`]: the full finite-element model, everything that does not change during a run
//! (the configuration, the bodies' mesh and terms, the sparsity pattern, the mass matrix, the
//! hinge, the torque and the wall), and the energies, scales and initial state it defines. The
//! reduced body is built from these operators ([`crate::reduced`]); the stepper
//! ([`crate::simulation`]) owns a body of either kind.
//!
//! Files: `body` (the bodies of a model: the pendulum and the others), `shared` (the operators
//! that the models of one mesh share), `fingerprint` (what a snapshot of the model is checked
//! against).

use std::sync::Arc;

pub mod body;
pub(crate) mod fingerprint;
pub mod shared;
mod state;

pub use body::{Body, BodySpec};
pub use fingerprint::{fingerprint, Fingerprint};
pub use shared::forget_shared;
pub use state::State;

use crate::assembly::{Dirichlet, Pattern};
use crate::config::{Config, ContactMethod, InitialAcceleration, TorqueProfile as ProfileKind, WallKind};
use crate::constraint::Hinge;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::post::NodalStress;
use crate::rigid::RigidProjection;
use crate::terms::inertia::{BodyMass, MassMatrix};
use crate::terms::{StepContext, Term, Torque, WallContact};
use shared::{shared, Key};

/// The name of the hinge boundary.
pub const HINGE_BOUNDARY: &str = "rotation";

/// The name of the head's outer arc, the boundary that touches the wall.
pub const CONTACT_BOUNDARY: &str = "contact_head";

/// With a wall, the pendulum released at `initial.angle_deg` must lie on the face's free side.
/// `pendulum` holds the pendulum's nodes only (a deformable wall's block stays where it is).
fn check_wall_clearance(config: &Config, pendulum: &Mesh) -> Result<(), Error> {
    if !config.wall.is_present() {
        return Ok(());
    }
    let (s, c) = config.initial.angle_deg.to_radians().sin_cos();
    let leftmost = pendulum
        .nodes
        .iter()
        .map(|p| c * p[0] - s * p[1])
        .fold(f64::INFINITY, f64::min);
    // touching is allowed (the tutorial's wall touches the hanging head); 1 nm for rounding
    if leftmost < config.wall.x - 1e-9 {
        return Err(Error::Config(format!(
            "wall.x = {} m: the pendulum released at initial.angle_deg = {} reaches x = {leftmost:.6} m, inside the \
             wall; allowed: wall.x <= {leftmost:.6} m for this angle (or a release angle that keeps the head off the wall)",
            config.wall.x, config.initial.angle_deg
        )));
    }
    Ok(())
}

/// The bodies after the pendulum: with `wall.kind = "deformable"` the contact tutorial's block
/// first (held on its left, top and bottom edges), then `others`.
fn with_wall_block(config: &Config, others: &[BodySpec]) -> Vec<BodySpec> {
    let mut all = others.to_vec();
    if config.wall.kind == WallKind::Deformable {
        let w = &config.wall;
        all.insert(
            0,
            BodySpec {
                name: "wall".into(),
                mesh: crate::mesh::block::wall_block(w),
                material: crate::config::Material {
                    youngs_modulus: w.youngs_modulus,
                    poisson_ratio: w.poisson_ratio,
                    density: w.density,
                    ..config.material.clone()
                },
                thickness: w.thickness,
                gravity: true,
                fixed: vec![crate::mesh::block::FIXED.into()],
            },
        );
    }
    all
}

/// The contact of the head's arc (on `pendulum`, the pendulum's view of `mesh`) with the wall of
/// `config`: the rigid half-plane or the deformable block's face; `None` without a wall.
fn wall_contact(config: &Config, pendulum: &Mesh, mesh: &Mesh) -> Result<Option<WallContact>, Error> {
    let (c, g) = (&config.contact, &config.geometry);
    let mut wall = match config.wall.kind {
        WallKind::None => return Ok(None),
        WallKind::Rigid => WallContact::new(
            pendulum,
            CONTACT_BOUNDARY,
            config.wall.x,
            c.stiffness,
            g.thickness,
            c.points_per_edge,
        )?,
        WallKind::Deformable => WallContact::deformable(
            mesh,
            CONTACT_BOUNDARY,
            crate::mesh::block::FACE,
            c.stiffness,
            g.thickness,
            c.points_per_edge,
            0.5 * g.head_radius,
        )?,
    };
    wall.end_point = c.method == ContactMethod::Penalty;
    Ok(Some(wall))
}

/// Everything that does not change during a run.
pub struct Model {
    /// The configuration.
    pub config: Config,
    /// The mesh of every body (the pendulum's nodes and elements first).
    pub mesh: Mesh,
    /// The bodies; the first is the pendulum ([`Model::pendulum`]).
    pub bodies: Vec<Body>,
    /// Fixed sparsity pattern (shared with the models of the same mesh and loads,
    /// [`shared`]).
    pub pattern: Arc<Pattern>,
    /// The fixed degrees of freedom of every body.
    pub fixed: Dirichlet,
    /// The actuator torque, when `[torque]` has a profile other than `"none"` (its profile is the
    /// configured one, or the value held by `Simulation::set_torque`).
    pub torque: Option<Torque>,
    /// The contact of the head with the wall: the rigid half-plane (`wall.kind = "rigid"`) or the
    /// face of the deformable block (`"deformable"`); `None` without a wall.
    pub wall: Option<WallContact>,
    /// FNV-1a hashes of the configuration's values (without `time.end`, `[output]` and file paths),
    /// the mesh and the torque table as read: a snapshot made for another model is refused
    /// (`Simulation::restore`).
    pub fingerprint: Fingerprint,
    /// Consistent mass matrix (shared as the pattern).
    pub mass: Arc<MassMatrix>,
    /// The hinge.
    pub hinge: Hinge,
    /// Proxy-angle functionals and rigid-body moments of area (of the pendulum; shared as the
    /// pattern).
    pub projection: Arc<RigidProjection>,
    /// [`Model::length_scale`], computed once (the steps ask for it).
    length: f64,
    /// `[largest nodal gravity force, the pendulum's weight]` \[N\], computed once (every step
    /// reads them).
    gravity_scales: [f64; 2],
}

impl Model {
    /// Builds every operator of the run (pattern, mass, terms, symbolic data) for the pendulum of
    /// `config` on `mesh`.
    pub fn new(config: &Config, mesh: Mesh) -> Result<Self, Error> {
        Self::with_bodies(config, mesh, &[])
    }

    /// As [`Model::new`], with further bodies after the pendulum (see [`body`]).
    pub fn with_bodies(config: &Config, mesh: Mesh, others: &[BodySpec]) -> Result<Self, Error> {
        Self::build_beside(config, mesh, others, |_| ()).map(|(model, ())| model)
    }

    /// As [`Model::with_bodies`], running `beside` on another thread while the operators are
    /// built, with the model's fingerprint (known before the operators): for work that depends
    /// on the model's inputs alone (a reduced body read from its cache).
    pub fn build_beside<R: Send>(
        config: &Config,
        mesh: Mesh,
        others: &[BodySpec],
        beside: impl FnOnce(&Fingerprint) -> R + Send,
    ) -> Result<(Self, R), Error> {
        config.validate()?;
        // before the bodies are built: a body's mesh view holds every body's nodes, and the
        // block's must not be turned with the pendulum
        check_wall_clearance(config, &mesh)?;
        let others = with_wall_block(config, others);
        let (mesh, parts) = body::parts(config, mesh, &others);
        let pendulum_view = &parts[0].view;
        let hinge = Hinge::new(pendulum_view, HINGE_BOUNDARY)?;
        let torque = match config.torque.profile {
            ProfileKind::None => None,
            _ => {
                let t = Torque::from_config(pendulum_view, HINGE_BOUNDARY, &config.torque)?;
                t.check_hub_stress(config.geometry.thickness, config.material.youngs_modulus)?;
                Some(t)
            }
        };
        let wall = wall_contact(config, pendulum_view, &mesh)?;
        let mut fingerprint = fingerprint(config, &mesh, torque.as_ref().and_then(|t| t.table.as_ref()));
        for spec in &others {
            // the other bodies' settings are not in the configuration
            let settings = format!(
                "{:?} {} {} {:?}",
                spec.material, spec.thickness, spec.gravity, spec.fixed
            );
            fingerprint.add_settings(settings.as_bytes());
        }
        let loads = torque
            .iter()
            .map(|t| t as &dyn Term)
            .chain(wall.iter().map(|t| t as &dyn Term));
        let entries: Vec<(usize, usize)> = loads.flat_map(|t| t.hessian_entries()).collect();
        let masses: Vec<BodyMass> = parts
            .iter()
            .map(|p| BodyMass {
                mesh: &p.view,
                first_element: p.elements.start,
                density: p.density,
                thickness: p.thickness,
            })
            .collect();
        // the keys of the operators shared with other models (see `shared`): the pattern's is the
        // mesh's and the loads' entries, the mass matrix's adds each body's density and thickness
        let mesh_key = Key::on(&mesh, fingerprint.mesh);
        let pattern_key = mesh_key.clone().with(entries.as_slice());
        let mass_key = parts.iter().fold(pattern_key.clone(), |k, p| {
            p.key(&k).with_f64(&[p.density, p.thickness])
        });
        // the bodies' terms and the work `beside` next to the pattern, the mass matrix and the
        // projection: independent data, made on two threads
        let ((bodies, beside), ((pattern, mass), projection)) = rayon::join(
            || {
                rayon::join(
                    || body::bodies(config, &parts, &others, &mesh_key),
                    || beside(&fingerprint),
                )
            },
            || {
                rayon::join(
                    || {
                        let pattern = shared(&pattern_key, || Pattern::new(&mesh, &entries));
                        let mass = shared(&mass_key, || MassMatrix::of_bodies(&pattern, &masses));
                        (pattern, mass)
                    },
                    || shared(&parts[0].key(&mesh_key), || RigidProjection::new(pendulum_view)),
                )
            },
        );
        let bodies = bodies?;
        let fixed = Dirichlet::new(
            &pattern,
            bodies.iter().flat_map(|b| b.fixed_dofs.iter().copied()).collect(),
        );
        let mut model = Self {
            config: config.clone(),
            mesh,
            bodies,
            pattern,
            fixed,
            torque,
            wall,
            fingerprint,
            mass,
            hinge,
            projection,
            length: 0.0,
            gravity_scales: [0.0; 2],
        };
        model.gravity_scales = [
            model
                .bodies
                .iter()
                .flat_map(|b| b.gravity.load_gradient.iter())
                .fold(0.0f64, |a, b| a.max(b.abs())),
            model.bodies[0].gravity.load_gradient.iter().sum::<f64>(),
        ];
        let pendulum = &model.mesh.nodes[model.bodies[0].nodes.clone()];
        model.length = pendulum.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
        Ok((model, beside))
    }

    /// The number of unknowns of a step of the full model: two displacement components per node
    /// and the hinge's two multipliers.
    pub fn unknowns(&self) -> usize {
        Self::unknowns_of(&self.mesh)
    }

    /// [`Model::unknowns`] of a model on `mesh`, before it is built.
    pub fn unknowns_of(mesh: &Mesh) -> usize {
        2 * mesh.num_nodes() + 2
    }

    /// The shortest of the bodies' wave times ([`Body::wave_time`]) \[s\]: how far
    /// `solver.max_cutbacks = "auto"` halves a failing step ([`crate::config::Cutbacks`]).
    pub fn wave_time(&self) -> f64 {
        self.bodies.iter().map(Body::wave_time).fold(f64::INFINITY, f64::min)
    }

    /// Largest distance of a node of the pendulum from the pivot \[m\].
    pub fn length_scale(&self) -> f64 {
        self.length
    }

    /// The pendulum (the first body).
    pub fn pendulum(&self) -> &Body {
        &self.bodies[0]
    }

    /// The conservative terms of every body with the factor of their Jacobian in the
    /// energy-momentum system (`1 + χ` for the strain energy, see [`crate::scheme::energy_momentum`]):
    /// strain energy and gravity, body after body.
    pub fn body_terms(&self, chi: f64) -> Vec<(&dyn Term, f64)> {
        self.bodies
            .iter()
            .flat_map(|b| [(&b.elastic as &dyn Term, 1.0 + chi), (&*b.gravity as &dyn Term, 1.0)])
            .collect()
    }

    /// Strain energy of every body \[J\].
    pub fn strain_energy(&self, u: &[f64], cx: &StepContext) -> f64 {
        self.bodies.iter().map(|b| b.elastic.energy(u, cx)).sum()
    }

    /// Gravitational energy of every body relative to the pivot height \[J\].
    pub fn gravity_energy(&self, u: &[f64], cx: &StepContext) -> f64 {
        self.bodies.iter().map(|b| b.gravity.energy(u, cx)).sum()
    }

    /// Largest nodal gravity force of any body \[N\].
    pub(crate) fn largest_gravity_force(&self) -> f64 {
        self.gravity_scales[0]
    }

    /// The pendulum's weight as the sum of its nodal gravity loads \[N\] (the energy balance's
    /// scale).
    pub(crate) fn pendulum_weight(&self) -> f64 {
        self.gravity_scales[1]
    }

    /// Nodal stresses of every body (each node belongs to one body).
    pub fn nodal_stress(&self, u: &[f64]) -> NodalStress {
        let mut out = self.bodies[0].nodal_stress(u);
        for b in &self.bodies[1..] {
            let other = b.nodal_stress(u);
            for n in b.nodes.clone() {
                out.cauchy[n] = other.cauchy[n];
                out.von_mises[n] = other.von_mises[n];
            }
            out.max_von_mises = out.max_von_mises.max(other.max_von_mises);
        }
        out
    }

    /// Largest nodal von Mises stress of any body \[Pa\].
    pub fn max_von_mises(&self, u: &[f64]) -> f64 {
        self.bodies
            .iter()
            .map(|b| b.stress.max_von_mises(&b.material, u))
            .fold(0.0, f64::max)
    }

    /// Mass of the pendulum \[kg\].
    pub fn mass_kg(&self) -> f64 {
        self.config.material.density * self.config.geometry.thickness * self.projection.area
    }

    /// The largest change of the pendulum's gravitational energy that its swing about the pivot
    /// allows from the initial angle \[J\]: `m g (d + |h₀|)`, with `d` the distance of the centroid
    /// from the pivot and `h₀` the centroid's initial height (the centroid moves on the circle of
    /// radius `d`, between the heights `−d` and `d`); 0 without gravity. With the initial kinetic
    /// energy and the torque's largest |work| it makes the energy a run has available, the scale of
    /// its energy balance (the run driver's energy audit).
    pub fn potential_range(&self) -> f64 {
        let p = &self.projection;
        let centroid = [p.first_moment[0] / p.area, p.first_moment[1] / p.area];
        let d = centroid[0].hypot(centroid[1]);
        let (s, c) = self.config.initial.angle_deg.to_radians().sin_cos();
        let h0 = s * centroid[0] + c * centroid[1];
        self.mass_kg() * self.config.gravity.g.abs() * (d + h0.abs())
    }

    /// The floor of every energy scale \[J\]: `10⁻³ m g₀ L` (`m` the pendulum's mass, `L` its
    /// largest distance from the pivot, `g₀ = 9.81 m/s²` also when gravity is off), a thousandth of
    /// the work to lift the body by its own length, for a body that nothing moves.
    pub fn energy_floor(&self) -> f64 {
        1e-3 * self.mass_kg() * 9.81 * self.length_scale()
    }

    /// Moment of inertia of the pendulum about the pivot \[kg m²\].
    pub fn inertia_pivot(&self) -> f64 {
        self.config.material.density * self.config.geometry.thickness * self.projection.polar
    }

    /// The actuator torque `M(t)` \[N m\] of the `[torque]` section (0 without). With
    /// `torque.follower = false` this is the moment in the reference position; a body turned by `θ`
    /// receives `M cos θ` ([`crate::terms::torque`]).
    /// A torque `held` as an input (see `Simulation::set_torque`) replaces the profile.
    pub fn applied_torque(&self, t: f64, held: Option<f64>) -> f64 {
        self.torque
            .as_ref()
            .map_or(0.0, |torque| held.unwrap_or_else(|| torque.value(t)))
    }

    /// The load terms after the bodies' own: the torque (if any), then the wall's contact (if any).
    pub fn loads(&self) -> impl Iterator<Item = &dyn Term> {
        self.torque
            .iter()
            .map(|t| t as &dyn Term)
            .chain(self.wall.iter().map(|t| t as &dyn Term))
    }

    /// Contact energy of the current state \[J\] (0 without a wall).
    pub fn contact_energy(&self, u: &[f64], cx: &StepContext) -> f64 {
        self.wall.as_ref().map_or(0.0, |w| w.energy(u, cx))
    }

    /// The moment of the actuator about the pivot when the body is rigidly turned by `theta` \[N m\]:
    /// `M(t)` for the follower torque, `M(t) cos θ` for the fixed-direction load.
    pub fn applied_moment_at(&self, t: f64, theta: f64, held: Option<f64>) -> f64 {
        if self.config.torque.follower {
            self.applied_torque(t, held)
        } else {
            self.applied_torque(t, held) * theta.cos()
        }
    }

    /// The initial state described by the configuration, with the torque `held` as an input if
    /// any (its rigid acceleration includes the torque).
    pub fn initial_state(&self, held: Option<f64>) -> State {
        let init = &self.config.initial;
        let theta = init.angle_deg.to_radians();
        let (s, c) = theta.sin_cos();
        let w = init.angular_velocity;
        let nn = self.mesh.num_nodes();
        let (mut u, mut v, mut a) = (vec![0.0; 2 * nn], vec![0.0; 2 * nn], vec![0.0; 2 * nn]);
        let rho_t = self.config.material.density * self.config.geometry.thickness;
        // moment of gravity about the pivot in the rotated position: −ρ t g ∫ x_x dA, x = R X
        let sx = c * self.projection.first_moment[0] - s * self.projection.first_moment[1];
        let tau_g = -rho_t * self.config.gravity.g * sx;
        let alpha = match init.acceleration {
            InitialAcceleration::Rigid => (tau_g + self.applied_moment_at(0.0, theta, held)) / self.inertia_pivot(),
            InitialAcceleration::Zero => 0.0,
        };
        let rigid_acc = init.acceleration == InitialAcceleration::Rigid;
        // the pendulum turns and moves; the other bodies start at rest, undeformed
        for (n, p) in self.mesh.nodes.iter().enumerate().take(self.bodies[0].nodes.end) {
            let x = [c * p[0] - s * p[1], s * p[0] + c * p[1]];
            u[2 * n] = x[0] - p[0];
            u[2 * n + 1] = x[1] - p[1];
            v[2 * n] = -w * x[1];
            v[2 * n + 1] = w * x[0];
            if rigid_acc {
                a[2 * n] = -alpha * x[1] - w * w * x[0];
                a[2 * n + 1] = alpha * x[0] - w * w * x[1];
            }
        }
        State { t: 0.0, u, v, a }
    }

    /// Current nodal positions `x = X + u`, interleaved.
    pub fn positions(&self, u: &[f64]) -> Vec<f64> {
        self.mesh
            .nodes
            .iter()
            .enumerate()
            .flat_map(|(n, p)| [p[0] + u[2 * n], p[1] + u[2 * n + 1]])
            .collect()
    }
}
