//! Orchestration: builds the model from a configuration and a mesh, sets the initial state, and
//! advances it step by step with cut-backs.
//!
//! **Initial state** (pivot at the origin, `R = R(θ₀)`): `u₀ = (R − I) X`, `v₀ = ω₀ e_z × x`,
//! `x = R X`. The initial acceleration is either zero (the tutorial's start) or the rigid-body value
//! `a₀ = α₀ e_z × x − ω₀² x`, with `α₀ = (τ_g + M(0)) / I_pivot` from the torque balance about the
//! pivot: `τ_g = −ρ t g ∫ x_x dA` is the moment of gravity and `I_pivot = ρ t ∫ |X|² dA`.
//!
//! With the rigid start the body is also put into elastic equilibrium with gravity, the torque
//! and the d'Alembert forces of that rigid motion: `u₀` minimises
//! `Π_el(u) + Π_g(u) + Π_torque(u, 0) + (M a₀)·u` under the hinge, starting from the rigid rotation.
//! The rotation about the pivot is a zero-energy mode of that static problem (its moment balance
//! is what fixes `α₀`), so a mass term `½ (u − u_rigid)ᵀ M (u − u_rigid) / (0.01 s)²` pins it (the
//! conditioning of an ordinary step);
//! its residual force is removed by re-centring it on the solution and solving again (proximal
//! point iterations, a few passes). Starting
//! undeformed instead excites axial vibrations that the trapezoidal rule never damps (the hinge
//! force then oscillates by 5e-5 of the weight for a pendulum at rest). The `"zero"` start is
//! the tutorial's: undeformed, at rest in its own frame (`initial.elastic = "undeformed"` also gives
//! an undeformed rigid start, for comparisons with codes that start that way).
//!
//! **Steps**: each user step `tₙ → tₙ + Δt` solves the energy-momentum system
//! ([`crate::energy_momentum`], the default) or minimises the Newmark incremental potential
//! ([`crate::newmark`]; `"trapezoidal"`, `"hht"`) with Newton ([`crate::newton`]). If Newton fails,
//! the step is split into two halves, recursively, as `solver.max_cutbacks` allows (by default
//! down to the mesh's wave time, [`crate::config::Cutbacks`]); then the run stops with an error
//! naming the step, the time and the last residual ([`Error::TimeStep`]).
//!
//! **Stepping interface** (`stepper`): [`Simulation::step`] with any `dt`, rollback of a failed
//! step, the held torque input, outputs on request; snapshots of the complete state
//! ([`Snapshot`], `snapshot`).

use crate::assembly::{Dirichlet, Pattern};
use crate::config::{
    Config, ContactMethod, InitialAcceleration, InitialElastic, Scheme, TorqueProfile as ProfileKind, WallKind,
};
use crate::constraint::Hinge;
use crate::energy_momentum::EnergyMomentum;
use crate::error::NewtonError;
use crate::linsolve::Cholesky;
use crate::newmark::{Newmark, State};
use crate::newton::{NewtonSettings, Solver, Timings};
use crate::post::{NodalStress, RigidProjection, Unwrap};
use crate::terms::inertia::{BodyMass, MassMatrix};
use crate::terms::{DiscreteGradient, Inertia, Linear, RigidWall, Scaled, StepContext, StepStart, Term, Torque};
use crate::{Error, Mesh};

pub mod body;
mod impact;
mod snapshot;
pub mod split;
mod stepper;

pub use body::{Body, BodySpec};
pub use impact::{ContactEvent, ContactEventKind};
pub use snapshot::{fingerprint, Fingerprint, Snapshot, SNAPSHOT_VERSION};
pub use stepper::Energies;

/// Relative equilibrium tolerance of a converged step: `‖∇Φ + Cᵀλ‖∞ ≤ 10⁻⁴ × load scale`, where the
/// load scale is the largest nodal gravity or inertia force. Together with the energy-norm criterion
/// (`solver.tolerance`) it guards against a small update that hides an unbalanced state.
pub const RESIDUAL_TOLERANCE: f64 = 1e-4;

/// The largest predicted turn of one energy-momentum (sub)step \[rad\]: a quarter turn. A light
/// body spun up by a torque (1800 rad/s at dt = 13 ms, 24 rad per step) is sub-stepped instead of
/// cut back from failure to failure.
const EM_MAX_TURN: f64 = std::f64::consts::FRAC_PI_2;

/// Passes of the proximal-point iteration of the initial equilibrium (see [`Simulation`]'s set-up).
const PROXIMAL_PASSES: usize = 4;

/// The name of the hinge boundary.
pub const HINGE_BOUNDARY: &str = "rotation";

/// The name of the head's outer arc, the boundary that touches the wall.
pub const CONTACT_BOUNDARY: &str = "contact_head";

/// With a wall, the pendulum released at `initial.angle_deg` must lie on the face's free side.
/// `pendulum` holds the pendulum's nodes only (a deformable wall's block stays where it is).
fn check_wall_clearance(config: &Config, pendulum: &Mesh) -> Result<(), Error> {
    if config.wall.kind == WallKind::None {
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

/// Everything that does not change during a run.
pub struct Model {
    /// The configuration.
    pub config: Config,
    /// The mesh of every body (the pendulum's nodes and elements first).
    pub mesh: Mesh,
    /// The bodies; the first is the pendulum ([`Model::pendulum`]).
    pub bodies: Vec<Body>,
    /// Fixed sparsity pattern.
    pub pattern: Pattern,
    /// The fixed degrees of freedom of every body.
    pub fixed: Dirichlet,
    /// The actuator torque, when `[torque]` has a profile other than `"none"` (its profile is the
    /// configured one, or the value held by [`Simulation::set_torque`]).
    pub torque: Option<Torque>,
    /// The rigid wall's contact with the head (`wall.kind = "rigid"`).
    pub wall: Option<RigidWall>,
    /// Further terms, added by later stages.
    pub extra_terms: Vec<Box<dyn Term>>,
    /// FNV-1a hashes of the configuration's values (without `time.end`, `[output]` and file paths),
    /// the mesh and the torque table as read: a [`Snapshot`] made for another model is refused
    /// ([`Simulation::restore`]).
    pub fingerprint: Fingerprint,
    /// Consistent mass matrix.
    pub mass: MassMatrix,
    /// The hinge.
    pub hinge: Hinge,
    /// Proxy-angle functionals and rigid-body moments of area (of the pendulum).
    pub projection: RigidProjection,
    /// Time integrator.
    pub newmark: Newmark,
    /// α of HHT-α (0: the trapezoidal rule).
    pub hht_alpha: f64,
    /// The time integration scheme.
    pub scheme: Scheme,
}

impl Model {
    /// Builds every operator of the run (pattern, mass, terms, symbolic data) for the pendulum of
    /// `config` on `mesh`.
    pub fn new(config: &Config, mesh: Mesh) -> Result<Self, Error> {
        Self::with_bodies(config, mesh, &[])
    }

    /// As [`Model::new`], with further bodies after the pendulum (see [`body`]).
    pub fn with_bodies(config: &Config, mesh: Mesh, others: &[BodySpec]) -> Result<Self, Error> {
        config.validate()?;
        // before the bodies are built: a body's mesh view holds every body's nodes, and the
        // block's must not be turned with the pendulum
        check_wall_clearance(config, &mesh)?;
        let pendulum_mesh = mesh;
        let mut others = others.to_vec();
        if config.wall.kind == WallKind::Deformable {
            // the contact tutorial's block: a second body, held on its left, top and bottom edges
            let w = &config.wall;
            others.insert(
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
        let (mesh, bodies) = body::build(config, pendulum_mesh, &others)?;
        let hinge = Hinge::new(&bodies[0].mesh, HINGE_BOUNDARY)?;
        let extra_terms: Vec<Box<dyn Term>> = Vec::new();
        let mut torque = None;
        if config.torque.profile != ProfileKind::None {
            let t = Torque::from_config(&bodies[0].mesh, HINGE_BOUNDARY, &config.torque)?;
            t.check_hub_stress(config.geometry.thickness, config.material.youngs_modulus)?;
            torque = Some(t);
        }
        let wall = match config.wall.kind {
            WallKind::None => None,
            WallKind::Rigid => {
                let mut wall = RigidWall::new(
                    &bodies[0].mesh,
                    CONTACT_BOUNDARY,
                    config.wall.x,
                    config.contact.stiffness,
                    config.geometry.thickness,
                    config.contact.points_per_edge,
                )?;
                wall.end_point = config.contact.method == ContactMethod::Penalty;
                Some(wall)
            }
            WallKind::Deformable => {
                let mut wall = RigidWall::deformable(
                    &mesh,
                    CONTACT_BOUNDARY,
                    crate::mesh::block::FACE,
                    config.contact.stiffness,
                    config.geometry.thickness,
                    config.contact.points_per_edge,
                    0.5 * config.geometry.head_radius,
                )?;
                wall.end_point = config.contact.method == ContactMethod::Penalty;
                Some(wall)
            }
        };
        let mut fingerprint = snapshot::fingerprint(config, &mesh, torque.as_ref().and_then(|t| t.table.as_ref()));
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
            .chain(wall.iter().map(|t| t as &dyn Term))
            .chain(extra_terms.iter().map(|t| t.as_ref()));
        let entries: Vec<(usize, usize)> = loads.flat_map(|t| t.hessian_entries()).collect();
        let pattern = Pattern::new(&mesh, &entries);
        let parts: Vec<BodyMass> = bodies
            .iter()
            .map(|b| BodyMass {
                mesh: &b.mesh,
                first_element: b.first_element,
                density: b.density,
                thickness: b.thickness,
            })
            .collect();
        let mass = MassMatrix::of_bodies(&pattern, &parts);
        let projection = RigidProjection::new(&bodies[0].mesh);
        let fixed = Dirichlet::new(
            &pattern,
            bodies.iter().flat_map(|b| b.fixed_dofs.iter().copied()).collect(),
        );
        // α of HHT-α; 0 gives exactly the average-acceleration rule (β = ¼, γ = ½)
        let hht_alpha = match config.time.scheme {
            Scheme::Trapezoidal | Scheme::EnergyMomentum => 0.0,
            Scheme::Hht => config.time.hht_alpha,
        };
        Ok(Self {
            config: config.clone(),
            mesh,
            bodies,
            pattern,
            fixed,
            torque,
            wall,
            extra_terms,
            fingerprint,
            mass,
            hinge,
            projection,
            newmark: Newmark::hht(hht_alpha),
            hht_alpha,
            scheme: config.time.scheme,
        })
    }

    /// The shortest of the bodies' wave times ([`Body::wave_time`]) \[s\]: how far
    /// `solver.max_cutbacks = "auto"` halves a failing step ([`crate::config::Cutbacks`]).
    pub fn wave_time(&self) -> f64 {
        self.bodies.iter().map(Body::wave_time).fold(f64::INFINITY, f64::min)
    }

    /// Largest distance of a node of the pendulum from the pivot \[m\].
    pub fn length_scale(&self) -> f64 {
        let pendulum = &self.mesh.nodes[self.bodies[0].nodes.clone()];
        pendulum.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max)
    }

    /// The pendulum (the first body).
    pub fn pendulum(&self) -> &Body {
        &self.bodies[0]
    }

    /// The conservative terms of every body with the factor of their Jacobian in the
    /// energy-momentum system (`1 + χ` for the strain energy, see [`crate::energy_momentum`]):
    /// strain energy and gravity, body after body.
    pub fn body_terms(&self, chi: f64) -> Vec<(&dyn Term, f64)> {
        self.bodies
            .iter()
            .flat_map(|b| [(&b.elastic as &dyn Term, 1.0 + chi), (&b.gravity as &dyn Term, 1.0)])
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
    fn largest_gravity_force(&self) -> f64 {
        self.bodies
            .iter()
            .flat_map(|b| b.gravity.load_gradient.iter())
            .fold(0.0f64, |a, b| a.max(b.abs()))
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
    /// A torque `held` as an input (see [`Simulation::set_torque`]) replaces the profile.
    pub fn applied_torque(&self, t: f64, held: Option<f64>) -> f64 {
        self.torque
            .as_ref()
            .map_or(0.0, |torque| held.unwrap_or_else(|| torque.value(t)))
    }

    /// The load terms after the bodies' own: the torque (if any), the wall's contact (if any), then
    /// [`Model::extra_terms`].
    pub fn loads(&self) -> impl Iterator<Item = &dyn Term> {
        self.torque
            .iter()
            .map(|t| t as &dyn Term)
            .chain(self.wall.iter().map(|t| t as &dyn Term))
            .chain(self.extra_terms.iter().map(|t| t.as_ref()))
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

/// One row of `results.csv`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepRecord {
    /// Step number (0: the initial state).
    pub step: usize,
    /// Time \[s\].
    pub time: f64,
    /// Proxy angle, unwrapped \[rad\].
    pub theta: f64,
    /// Best-fit angular velocity \[rad/s\].
    pub omega: f64,
    /// Best-fit angular acceleration \[rad/s²\].
    pub alpha: f64,
    /// Kinetic energy \[J\].
    pub kinetic: f64,
    /// Strain energy \[J\].
    pub strain: f64,
    /// Gravitational energy relative to the pivot height \[J\].
    pub gravity: f64,
    /// Sum of the three \[J\].
    pub total: f64,
    /// Force of the hinge on the body \[N\].
    pub hinge_force: [f64; 2],
    /// Largest von Mises stress \[Pa\].
    pub von_mises_max: f64,
    /// Newton iterations of the step (0 for the initial state).
    pub newton_iterations: usize,
    /// Actuator torque `M(t)` \[N m\] (see [`Model::applied_torque`]).
    pub torque: f64,
    /// Work done by the actuator since the start \[J\]; `total − total(0)` equals it up to the
    /// integrator's energy error.
    pub torque_work: f64,
    /// Angular momentum about the pivot, `∫ ρ t x × v dA` \[kg m²/s\].
    pub angular_momentum: f64,
    /// The contact with the wall, when the model has one.
    pub contact: Option<ContactRecord>,
}

/// The contact columns of a [`StepRecord`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactRecord {
    /// Smallest signed distance from the head's arc to the wall face \[m\] (negative: penetration).
    pub gap: f64,
    /// Normal force of the wall on the head \[N\].
    pub force: f64,
    /// Contact energy \[J\] (part of `total`).
    pub energy: f64,
    /// Impacts so far.
    pub impacts: usize,
}

impl StepRecord {
    /// CSV header, in this order (without a wall).
    pub const HEADER: &'static str = "time_s,theta_rad,omega_rad_s,alpha_rad_s2,kinetic_J,strain_J,gravity_J,total_J,\
hinge_fx_N,hinge_fy_N,von_mises_max_Pa,newton_iterations,torque_Nm,torque_work_J,angular_momentum_kg_m2_s";

    /// The columns a model with a wall adds after [`StepRecord::HEADER`].
    pub const CONTACT_HEADER: &'static str = "gap_m,contact_force_N,contact_J,impacts";

    /// The CSV header of a run with (`contact`) or without a wall.
    pub fn header(contact: bool) -> String {
        if contact {
            format!("{},{}", Self::HEADER, Self::CONTACT_HEADER)
        } else {
            Self::HEADER.to_string()
        }
    }
}

/// The state of the pendulum at one written time, with everything the frame writers need.
/// All arrays are per mesh node (vertices and mid-edge nodes).
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    /// Step number (0 is the initial state).
    pub step: usize,
    /// Time \[s\].
    pub time: f64,
    /// Rigid-body proxy angle \[rad\] (unwrapped).
    pub theta: f64,
    /// Displacement \[m\].
    pub displacement: &'a [[f64; 2]],
    /// Velocity \[m/s\].
    pub velocity: &'a [[f64; 2]],
    /// Acceleration \[m/s²\].
    pub acceleration: &'a [[f64; 2]],
    /// Plane-stress von Mises stress \[Pa\].
    pub von_mises: &'a [f64],
    /// Cauchy stress `[σxx, σyy, σxy]` \[Pa\].
    pub cauchy: &'a [[f64; 3]],
}

/// Nodal fields of the current state, owned, for the frame writers.
#[derive(Clone, Debug, Default)]
pub struct FrameData {
    /// Step number.
    pub step: usize,
    /// Time \[s\].
    pub time: f64,
    /// Proxy angle \[rad\].
    pub theta: f64,
    /// Displacement per node.
    pub displacement: Vec<[f64; 2]>,
    /// Velocity per node.
    pub velocity: Vec<[f64; 2]>,
    /// Acceleration per node.
    pub acceleration: Vec<[f64; 2]>,
    /// Nodal stresses.
    pub stress: NodalStress,
}

impl FrameData {
    /// Borrowed view for the writers.
    pub fn as_frame(&self) -> Frame<'_> {
        Frame {
            step: self.step,
            time: self.time,
            theta: self.theta,
            displacement: &self.displacement,
            velocity: &self.velocity,
            acceleration: &self.acceleration,
            von_mises: &self.stress.von_mises,
            cauchy: &self.stress.cauchy,
        }
    }
}

fn pairs(v: &[f64]) -> Vec<[f64; 2]> {
    v.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
}

/// A running simulation.
pub struct Simulation {
    /// The model.
    pub model: Model,
    /// Newton workspace (factorisation, buffers).
    pub solver: Solver,
    /// Current state.
    pub state: State,
    /// Current hinge multipliers \[N\].
    pub lambda: [f64; 2],
    /// Steps done.
    pub step: usize,
    /// Newton iterations (linear solves) so far.
    pub total_iterations: usize,
    /// Numeric factorisations so far.
    pub total_factorizations: usize,
    /// Cut-backs so far.
    pub cutbacks: usize,
    /// Work of the external loads of the extra terms (the torque) since the start \[J\].
    pub torque_work: f64,
    unwrap: Unwrap,
    /// Proxy angle of the current state, unwrapped \[rad\].
    theta: f64,
    /// The time of the state as `base + count · dt` over a run of equal steps.
    clock: Clock,
    /// Newton iterations of the last step (0 before the first).
    last_iterations: usize,
    /// The torque value held by [`Simulation::set_torque`] \[N m\], if any.
    held_torque: Option<f64>,
    /// Nodal stress evaluations so far ([`Simulation::stress_evaluations`]).
    stress_evaluations: usize,
    /// Impacts so far.
    impacts: usize,
    /// Contact events so far (append-only within a run: roll-backs truncate it).
    events: Vec<ContactEvent>,
    /// Contact events copied by snapshots and restores ([`Simulation::events_copied`]).
    events_copied: std::sync::atomic::AtomicUsize,
    /// The impact in progress.
    contact_phase: Option<impact::ContactPhase>,
    /// Whether the sub-steps inside impacts are recorded ([`Simulation::record_impacts`]).
    recording_impacts: bool,
    /// The records of the sub-steps inside impacts not yet taken
    /// ([`Simulation::take_impact_records`]; roll-backs truncate it).
    impact_records: Vec<StepRecord>,
    /// The sub-step ends of the impact in progress, for the predictor of a chattering contact.
    impact_trail: impact::ImpactTrail,
    scratch: Vec<f64>,
    /// `(t, α)` at the start of the previous (sub)step, for the predictor's `α̇`.
    previous_alpha: Option<(f64, f64)>,
    /// Rigid-body measures of the current state, once computed.
    rates: Option<Kinematics>,
    /// `M x` of the current positions (valid with `rates`).
    mx: Vec<f64>,
    /// For [`Simulation::acceleration_field`]: the mass matrix factorised, the hinge rows and
    /// `M⁻¹Cᵀ`, made on first use.
    mass_solver: Option<(Cholesky, [Vec<f64>; 2], Vec<f64>)>,
}

/// The time of the state as `base + count · dt`: over a run of steps of the same `dt` the time
/// is computed, not accumulated (`n · dt` exactly for a run from 0, as `advance` always did), and
/// any other step starts a new run at the time reached.
#[derive(Clone, Copy, Debug)]
struct Clock {
    base: f64,
    dt: f64,
    count: u64,
}

/// Equal bit for bit (`dt` is NaN before a run).
impl PartialEq for Clock {
    fn eq(&self, other: &Self) -> bool {
        self.base.to_bits() == other.base.to_bits()
            && self.dt.to_bits() == other.dt.to_bits()
            && self.count == other.count
    }
}

impl Clock {
    /// t = 0, no run yet.
    const START: Self = Self {
        base: 0.0,
        dt: f64::NAN,
        count: 0,
    };

    /// The time \[s\].
    fn time(&self) -> f64 {
        if self.count == 0 {
            self.base
        } else {
            self.base + self.count as f64 * self.dt
        }
    }

    /// The clock after one more step of `dt`.
    fn after(&self, dt: f64) -> Self {
        if dt.to_bits() == self.dt.to_bits() {
            Self {
                count: self.count + 1,
                ..*self
            }
        } else {
            Self {
                base: self.time(),
                dt,
                count: 1,
            }
        }
    }

    /// A clock standing at exactly `t`.
    fn at(t: f64) -> Self {
        Self {
            base: t,
            dt: f64::NAN,
            count: 0,
        }
    }
}

/// Rigid-body measures of a state (see [`Simulation::kinematics`]).
#[derive(Clone, Copy, Debug)]
struct Kinematics {
    /// Best-fit angular velocity \[rad/s\].
    omega: f64,
    /// Best-fit angular acceleration \[rad/s²\].
    alpha: f64,
    /// Kinetic energy \[J\].
    kinetic: f64,
    /// Angular momentum about the pivot \[kg m²/s\].
    momentum: f64,
}

impl Simulation {
    /// Sets up the run: operators, symbolic factorisation, initial state.
    pub fn new(model: Model) -> Result<Self, Error> {
        let solver = Solver::with_bodies(
            &model.pattern,
            &model.hinge,
            model.fixed.clone(),
            2 * model.bodies[0].nodes.end,
        )?;
        let state = model.initial_state(None);
        let mut sim = Self {
            theta: 0.0,
            clock: Clock::START,
            last_iterations: 0,
            held_torque: None,
            stress_evaluations: 0,
            impacts: 0,
            events: Vec::new(),
            events_copied: Default::default(),
            contact_phase: None,
            recording_impacts: false,
            impact_records: Vec::new(),
            impact_trail: impact::ImpactTrail::default(),
            solver,
            state,
            lambda: [0.0; 2],
            step: 0,
            total_iterations: 0,
            total_factorizations: 0,
            cutbacks: 0,
            torque_work: 0.0,
            unwrap: Unwrap::default(),
            scratch: Vec::new(),
            previous_alpha: None,
            rates: None,
            mx: Vec::new(),
            mass_solver: None,
            model,
        };
        sim.initialize()?;
        Ok(sim)
    }

    /// Sets the initial state of the configuration (with the current torque input): the rigid
    /// motion, the hinge force of its balance of linear momentum, the elastic equilibrium.
    fn initialize(&mut self) -> Result<(), Error> {
        let sim = self;
        sim.state = sim.model.initial_state(sim.held_torque);
        sim.rates = None;
        // the branch of the hub angle: the initial angle
        sim.theta = sim.model.config.initial.angle_deg.to_radians();
        // The multipliers of the initial state from the balance of linear momentum:
        // −λ = ∫ ρ t a dA − F_gravity  (the force the hinge must exert on the body).
        let mut ma = vec![0.0; sim.state.a.len()];
        sim.model.mass.apply(&sim.state.a, &mut ma);
        let pendulum = &sim.model.bodies[0];
        let (ma, weight) = (
            &ma[..2 * pendulum.nodes.end],
            pendulum.gravity.load_gradient.iter().sum::<f64>(),
        );
        let fx: f64 = ma.iter().step_by(2).sum();
        let fy: f64 = ma.iter().skip(1).step_by(2).sum::<f64>() + weight;
        sim.lambda = [-fx, -fy];
        if sim.model.config.initial.elastic_state() == InitialElastic::Equilibrium {
            sim.equilibrate()?;
        }
        let theta0 = sim.model.projection.angle(&sim.state.u);
        sim.unwrap = Unwrap::starting_at(theta0);
        sim.theta = theta0;
        Ok(())
    }

    /// Puts the initial rigid state into elastic equilibrium (see the module doc).
    fn equilibrate(&mut self) -> Result<(), Error> {
        let m = &self.model;
        let mut inertial = vec![0.0; self.state.a.len()];
        m.mass.apply(&self.state.a, &mut inertial);
        let dalembert = Linear { gradient: inertial };
        let cx = StepContext::at(&self.state.u, self.state.t, self.theta, self.held_torque);
        let load_scale = dalembert
            .gradient
            .iter()
            .fold(1e-12f64, |a, b| a.max(b.abs()))
            .max(m.largest_gravity_force());
        let settings = NewtonSettings {
            tolerance: m.config.solver.tolerance,
            // a static problem, not a time step: at least 20 iterations whatever solver.max_iterations
            max_iterations: m.config.solver.max_iterations.max(20),
            residual_tolerance: RESIDUAL_TOLERANCE,
            load_scale,
            length_scale: m.length_scale(),
            frame_angle: m.projection.angle(&self.state.u),
            matrix_key: -1.0,
            reuse: false,
            residual_turn: 0.0,
        };
        let mut u = self.state.u.clone();
        let mut lambda = self.lambda;
        // Proximal-point iterations: re-centre the pin on the last solution so that its force,
        // c M (u − u_pin), vanishes in the limit; the elastic modes converge by the factor
        // c M / K ≈ 1e-6 per pass for steel, the rotation stays pinned.
        for pass in 0..PROXIMAL_PASSES {
            // the passes differ only by the pin's centre: later passes reuse the first's factorisation
            let settings = NewtonSettings {
                reuse: pass > 0,
                ..settings
            };
            let pin = Inertia {
                mass: &m.mass,
                pattern: &m.pattern,
                factor: 1e4,
                predictor: u.clone(),
            };
            let mut terms: Vec<&dyn Term> = vec![&pin];
            terms.extend(m.body_terms(0.0).into_iter().map(|(t, _)| t));
            terms.push(&dalembert);
            terms.extend(m.loads());
            let before = u.clone();
            self.solver
                .minimize(&m.pattern, &terms, &cx, &mut u, &mut lambda, &settings)
                .map_err(|source| Error::InitialEquilibrium { source })?;
            let change = u.iter().zip(&before).fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            if change < 1e-15 {
                break;
            }
        }
        self.state.u = u;
        self.lambda = lambda;
        self.rates = None;
        Ok(())
    }

    /// Builds model and simulation from a configuration and a mesh.
    pub fn from_config(config: &Config, mesh: Mesh) -> Result<Self, Error> {
        Self::new(Model::new(config, mesh)?)
    }

    /// Accumulated solver timings.
    pub fn timings(&self) -> Timings {
        self.solver.timings
    }

    /// Post-processes the current state into a CSV record.
    pub fn record(&mut self, newton_iterations: usize) -> StepRecord {
        let theta = self.theta;
        let von_mises_max = self.von_mises_max();
        let Kinematics {
            omega,
            alpha,
            kinetic,
            momentum,
        } = self.kinematics();
        let cx = self.context();
        let m = &self.model;
        let s = &self.state;
        let strain = m.strain_energy(&s.u, &cx);
        let gravity = m.gravity_energy(&s.u, &cx);
        let contact = m.wall.as_ref().map(|w| ContactRecord {
            gap: w.smallest_gap(&s.u),
            force: w.normal_force(&s.u),
            energy: w.energy(&s.u, &cx),
            impacts: self.impacts,
        });
        let contact_energy = contact.map_or(0.0, |c| c.energy);
        StepRecord {
            step: self.step,
            time: s.t,
            theta,
            omega,
            alpha,
            kinetic,
            strain,
            gravity,
            total: kinetic + strain + gravity + contact_energy,
            hinge_force: Hinge::reaction(self.lambda),
            von_mises_max,
            newton_iterations,
            torque: m.applied_torque(s.t, self.held_torque),
            torque_work: self.torque_work,
            angular_momentum: momentum,
            contact,
        }
    }

    /// The [`StepContext`] of the current state by itself (its time, unwrapped θ and held inputs).
    pub fn context(&self) -> StepContext<'_> {
        StepContext::at(&self.state.u, self.state.t, self.theta, self.held_torque)
    }

    /// Angular momentum about the pivot of the current state, `Σ_ab M_ab x_a × v_b` \[kg m²/s\].
    pub fn angular_momentum(&mut self) -> f64 {
        self.kinematics().momentum
    }

    /// Nodal fields of the current state.
    pub fn frame_data(&mut self, theta: f64) -> FrameData {
        let acceleration = pairs(&self.acceleration_field());
        FrameData {
            step: self.step,
            time: self.state.t,
            theta,
            displacement: pairs(&self.state.u),
            velocity: pairs(&self.state.v),
            acceleration,
            stress: self.nodal_stress(),
        }
    }

    /// The nodal acceleration of the current state \[m/s²\]. The Newmark schemes carry it in the
    /// state. The energy-momentum scheme does not need one (it keeps the step's mean acceleration
    /// as a load scale); here the consistent value at the end of the step is solved from the
    /// equation of motion, `M a = −∇Π(u, t) − Cᵀμ`, `C a = 0`, with a Cholesky factorisation of the
    /// mass matrix made on the first call (on request only: frames, not every step).
    pub fn acceleration_field(&mut self) -> Vec<f64> {
        if self.model.scheme != Scheme::EnergyMomentum || self.step == 0 {
            return self.state.a.clone();
        }
        if self.mass_solver.is_none() {
            let m = &self.model;
            let mut chol = Cholesky::new(&m.pattern).expect("the symbolic analysis succeeded at set-up");
            let mut mass = m.mass.values.clone();
            m.fixed.apply_matrix(&mut mass);
            chol.factor(&m.pattern, &mass)
                .expect("a consistent mass matrix is positive definite");
            let n = m.pattern.n;
            let rows = m.hinge.dense_rows(n);
            let mut columns = [rows[0].clone(), rows[1].clone()].concat();
            chol.solve_in_place(&mut columns);
            self.mass_solver = Some((chol, rows, columns));
        }
        let m = &self.model;
        let s = &self.state;
        let cx = StepContext::at(&s.u, s.t, self.theta, self.held_torque);
        let mut force = vec![0.0; s.u.len()];
        for (term, _) in m.body_terms(0.0) {
            term.add_gradient(&s.u, &cx, &mut force);
        }
        for term in m.loads() {
            term.add_gradient(&s.u, &cx, &mut force);
        }
        force.iter_mut().for_each(|f| *f = -*f);
        m.fixed.apply_vector(&mut force);
        let (chol, rows, columns) = self.mass_solver.as_mut().expect("made above");
        chol.solve_in_place(&mut force);
        // C (y − Z μ) = 0 with Z = M⁻¹Cᵀ: a 2×2 system for μ
        let n = force.len();
        let (zx, zy) = columns.split_at(n);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let sm = [
            [dot(&rows[0], zx), dot(&rows[0], zy)],
            [dot(&rows[1], zx), dot(&rows[1], zy)],
        ];
        let b = [dot(&rows[0], &force), dot(&rows[1], &force)];
        let det = sm[0][0] * sm[1][1] - sm[0][1] * sm[1][0];
        let mu = [
            (b[0] * sm[1][1] - b[1] * sm[0][1]) / det,
            (sm[0][0] * b[1] - sm[1][0] * b[0]) / det,
        ];
        (0..n).map(|i| force[i] - zx[i] * mu[0] - zy[i] * mu[1]).collect()
    }

    /// The largest nodal applied force: gravity, the inertia force `M a` of the current state, and for
    /// the actuator torque at time `t` the largest nodal inertia force of the rigid angular
    /// acceleration it drives, `|M(t)|/I · max_a |(M_mass (e_z × x))_a|` \[N\]. (The torque's own nodal
    /// forces sit on the short hinge edge and are about a hundred times the nodal gravity forces;
    /// as a scale they would loosen the residual check for the whole body.)
    fn load_scale(&mut self, t: f64) -> f64 {
        self.kinematics();
        let m = &self.model;
        self.scratch.resize(self.state.a.len(), 0.0);
        m.mass.apply(&self.state.a, &mut self.scratch);
        let inertia = self.scratch.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let gravity = m.largest_gravity_force();
        let torque = m.applied_torque(t, self.held_torque).abs();
        let mut driven = 0.0;
        if torque > 0.0 {
            // M (e_z × x) = e_z × (M x): the nodal inertia forces of a unit angular acceleration
            let largest = self.mx.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            driven = torque / m.inertia_pivot() * largest;
        }
        (inertia + gravity + driven).max(1e-12)
    }

    /// Best-fit angular velocity and acceleration of the current state \[rad/s, rad/s²\].
    pub fn angular_rates(&mut self) -> (f64, f64) {
        let k = self.kinematics();
        (k.omega, k.alpha)
    }

    /// Rigid-body measures of the current state (cached until the state changes). With
    /// `m_x = M x` for the positions `x = X + u`: `∫ ρ t |x|² dA = x·m_x`, and since `M` is symmetric
    /// and acts on both components alike, `Σ_ab M_ab x_a × w_b = Σ_b (m_x)_b × w_b` for any field `w`:
    /// one mass product serves the angular velocity, the angular momentum and the angular
    /// acceleration; a second one (`M v`) the kinetic energy.
    fn kinematics(&mut self) -> Kinematics {
        if let Some(k) = self.rates {
            return k;
        }
        let m = &self.model;
        // the pendulum's positions (zeros at the other bodies' nodes: the rigid-body measures are
        // the pendulum's; the mass matrix couples no two bodies, so M x stays the pendulum's)
        let mut x = m.positions(&self.state.u);
        x[2 * m.bodies[0].nodes.end..].iter_mut().for_each(|c| *c = 0.0);
        self.mx.resize(x.len(), 0.0);
        m.mass.apply(&x, &mut self.mx);
        let mx = &self.mx;
        let cross = |w: &[f64]| -> f64 {
            (0..x.len() / 2)
                .map(|b| mx[2 * b] * w[2 * b + 1] - mx[2 * b + 1] * w[2 * b])
                .sum()
        };
        let polar: f64 = x.iter().zip(mx).map(|(a, b)| a * b).sum();
        let momentum = cross(&self.state.v);
        let alpha = if m.scheme == Scheme::EnergyMomentum && self.step > 0 {
            // the consistent end-of-step value: the moment of the external loads at x (the strain
            // energy's forces and the hinge force have none) over the polar moment of inertia
            self.scratch.resize(x.len(), 0.0);
            self.scratch.iter_mut().for_each(|g| *g = 0.0);
            let cx = StepContext::at(&self.state.u, self.state.t, self.theta, self.held_torque);
            m.bodies[0].gravity.add_gradient(&self.state.u, &cx, &mut self.scratch);
            for term in m.loads() {
                term.add_gradient(&self.state.u, &cx, &mut self.scratch);
            }
            let moment: f64 = (0..x.len() / 2)
                .map(|a| x[2 * a + 1] * self.scratch[2 * a] - x[2 * a] * self.scratch[2 * a + 1])
                .sum();
            moment / polar
        } else {
            cross(&self.state.a) / polar
        };
        self.scratch.resize(x.len(), 0.0);
        m.mass.apply(&self.state.v, &mut self.scratch);
        let kinetic = 0.5 * self.state.v.iter().zip(&self.scratch).map(|(a, b)| a * b).sum::<f64>();
        let k = Kinematics {
            omega: momentum / polar,
            alpha,
            kinetic,
            momentum,
        };
        self.rates = Some(k);
        k
    }

    /// Starting guess of a step: the current configuration rotated rigidly about the pivot by
    /// `Δφ = ω Δt + ½ α Δt² + ¼ α̇ Δt³` (best-fit rates; `α̇` from the previous step). Extrapolating displacements linearly instead,
    /// `u + Δt v + ½Δt² a`, stretches a rotating body isotropically by `~ω α Δt³`: for steel a spurious
    /// stress of megapascals whose geometric stiffness can make the tangent indefinite. The rotation
    /// about the pivot keeps the hinge's mean displacement zero (the hinge edge is centred on it).
    fn rotational_guess(&mut self, dt: f64) -> Vec<f64> {
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
    fn try_step(&mut self, dt: f64, correct: bool) -> Result<(State, [f64; 2], usize), NewtonError> {
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

    /// Advances by `dt`, halving on failure; returns the Newton iterations used.
    fn advance_by(&mut self, dt: f64) -> Result<usize, (NewtonError, f64)> {
        self.advance_split(dt, 0, 0).map(|(its, _)| its)
    }

    /// [`Simulation::advance_by`] of the interval `dt` at cut-back depth `depth` (halved that many
    /// times), split without an attempt down to `start` (the depth the sub-step before it was
    /// taken at); returns the Newton iterations (those of the attempts that failed and were
    /// halved included) and the depth of its last sub-step.
    ///
    /// Why a halved interval's second half starts at the depth its first half ended at, and not
    /// with an attempt at its own length: a failed attempt runs out of Newton iterations (up to
    /// `solver.max_iterations`; at the last depth a second attempt without the GMRES correction,
    /// see [`Solver::solve`]), ten times the cost
    /// of a sub-step that converges. Where a local event needs sub-steps seven halvings down
    /// (seed 18's case 12 of `tests/robustness.rs`, see [`crate::config::Cutbacks`]), retrying
    /// every level on the way back up made 127 failed attempts per output step beside its 128
    /// sub-steps; now 7. The next output step starts again at its full length.
    fn advance_split(&mut self, dt: f64, depth: usize, start: usize) -> Result<(usize, usize), (NewtonError, f64)> {
        // the iterations of the attempts at this interval that failed
        let mut failed = 0;
        if depth >= start {
            let rates = (self.state.t, self.angular_rates().1);
            let mut attempt = self.try_step(dt, true);
            // asked only on a failure: the wave time goes over every element
            let halvable = attempt.is_err()
                && self
                    .model
                    .config
                    .solver
                    .max_cutbacks
                    .allows(depth, dt, self.model.wave_time());
            // where no halving is left, the step is tried once more without the GMRES correction
            // (see `Solver::solve`)
            if let Err(e) = &attempt {
                if !halvable && self.model.scheme == Scheme::EnergyMomentum {
                    failed = e.iterations();
                    attempt = self.try_step(dt, false);
                }
            }
            match attempt {
                Ok((state, lambda, its)) => {
                    self.previous_alpha = Some(rates);
                    self.rates = None;
                    let old = &self.state;
                    let cx = StepContext {
                        t: state.t,
                        t0: old.t,
                        dt,
                        u0: &old.u,
                        theta0: self.theta,
                        torque: self.held_torque,
                    };
                    self.torque_work += self
                        .model
                        .loads()
                        .map(|term| term.external_work(&state.u, &cx))
                        .sum::<f64>();
                    self.state = state;
                    self.lambda = lambda;
                    // the branch of θ for the next (sub)step's context
                    self.theta = self.unwrap.next(self.model.projection.angle(&self.state.u));
                    return Ok((failed + its, depth));
                }
                Err(e) if halvable => {
                    self.cutbacks += 1;
                    failed = e.iterations();
                }
                Err(e) => return Err((e, dt)),
            }
        }
        let (a, last) = self.advance_split(0.5 * dt, depth + 1, start)?;
        let (b, last) = self.advance_split(0.5 * dt, depth + 1, last)?;
        Ok((failed + a + b, last))
    }

    /// Advances one step of `time.dt` ([`Simulation::step`]) and returns its record (with the
    /// nodal stresses of [`StepRecord::von_mises_max`]).
    ///
    /// A step whose predicted rotation `|ω| Δt + ½ |α| Δt²` exceeds `time.max_rotation_deg` is split
    /// into 2, 4, 8, … equal sub-steps (powers of two, so the sub-step changes rarely). The
    /// trapezoidal rule advances a rotation along chords and loses about `Δφ²/12` of the angular
    /// rate per step; the default 3° keeps that below 2.3e-4 and never splits the tutorial's swing
    /// (at most 1.3° per step).
    pub fn advance(&mut self) -> Result<StepRecord, Error> {
        let its = self.step(self.model.config.time.dt)?;
        Ok(self.record(its))
    }

    /// One output step of length `dt`: sub-steps (the Newmark schemes beyond
    /// `time.max_rotation_deg`, see [`Simulation::advance`]; the energy-momentum scheme beyond a
    /// quarter turn, [`EM_MAX_TURN`]), cut-backs, the step counter; returns the Newton iterations.
    fn advance_over(&mut self, dt: f64) -> Result<usize, Error> {
        let t0 = self.state.t;
        let (omega, alpha) = self.angular_rates();
        let turn = omega.abs() * dt + 0.5 * alpha.abs() * dt * dt;
        // the energy-momentum scheme conserves at any step, but its step must turn the body by
        // less than half a turn (the hub and proxy angles are unwrapped step to step, and Newton's
        // rotated tangent degrades long before): a quarter turn at most per sub-step
        let limit = match self.model.scheme {
            Scheme::EnergyMomentum => EM_MAX_TURN,
            _ => self.model.config.time.max_rotation_deg.to_radians(),
        };
        let substeps = ((turn / limit).ceil() as usize).max(1).next_power_of_two();
        let h = dt / substeps as f64;
        let mut its = 0;
        let failed = |step: usize| {
            move |(source, dt_min)| Error::TimeStep {
                step,
                t: t0,
                dt: dt_min,
                source,
            }
        };
        if self.resolves_impacts() {
            its = self.advance_resolving(dt)?;
        } else {
            for _ in 0..substeps {
                let u0 = self.model.wall.is_some().then(|| self.state.u.clone());
                its += self.advance_by(h).map_err(failed(self.step + 1))?;
                if let Some(u0) = u0 {
                    self.check_contact_step(self.step + 1, t0, &u0)?;
                    self.contact_step_ends(&u0, h);
                }
            }
        }
        self.step += 1;
        self.total_iterations += its;
        Ok(its)
    }

    /// Advances one step from the current time to `t_end` (> the current time) and returns its
    /// record, with the time set to exactly `t_end` ([`Simulation::step_to`]).
    pub fn advance_to(&mut self, t_end: f64) -> Result<StepRecord, Error> {
        let its = self.step_to(t_end)?;
        Ok(self.record(its))
    }
}
