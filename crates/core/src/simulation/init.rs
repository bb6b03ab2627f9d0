//! Setting up a [`Simulation`]: the model and its body, the initial state of the configuration,
//! the hinge force of its rigid motion, and the body's own initial state (the equations are in
//! the module doc of [`crate::simulation`]).

use super::dynamics::Dynamics;
use super::impact::Impacts;
use super::{Clock, Model, Now, Simulation};
use crate::config::Config;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::rigid::Unwrap;

impl Simulation {
    /// Sets up the run of `model`: its body (the kind of `model.kind`) and the initial state.
    pub fn new(model: Model) -> Result<Self, Error> {
        let body = Dynamics::new(&model, None)?;
        Self::with_body(model, body)
    }

    /// Builds model and simulation from a configuration and a mesh.
    pub fn from_config(config: &Config, mesh: Mesh) -> Result<Self, Error> {
        let (model, prepared) =
            Model::build_beside(config, mesh, &[], |fingerprint| Dynamics::prepare(config, fingerprint))?;
        let body = Dynamics::new(&model, prepared)?;
        Self::with_body(model, body)
    }

    /// Builds the simulation of `config` on its own mesh (generated, or read from `mesh.file`):
    /// the one set-up of the run driver, the FMU, the Python package and the benchmarks.
    pub fn build(config: &Config) -> Result<Built, Error> {
        let start = std::time::Instant::now();
        let mesh = crate::mesh::generate(config)?;
        let mesh_warning = crate::mesh::max_size_warning(config, &mesh);
        let mesh_seconds = start.elapsed().as_secs_f64();
        let setup = std::time::Instant::now();
        let simulation = Self::from_config(config, mesh)?;
        Ok(Built {
            simulation,
            mesh_seconds,
            setup_seconds: setup.elapsed().as_secs_f64(),
            mesh_warning,
        })
    }

    fn with_body(model: Model, body: Dynamics) -> Result<Self, Error> {
        let state = model.initial_state(None);
        let mut sim = Self {
            now: Now {
                state,
                lambda: [0.0; 2],
                theta: 0.0,
                unwrap: Unwrap::default(),
                held_torque: None,
                torque_work: 0.0,
                rates: None,
                energies: None,
            },
            body,
            contact: Impacts::default(),
            step: 0,
            total_iterations: 0,
            total_factorizations: 0,
            cutbacks: 0,
            clock: Clock::START,
            last_iterations: 0,
            stress_evaluations: 0,
            events_copied: Default::default(),
            mass_solver: None,
            model,
        };
        sim.initialize()?;
        Ok(sim)
    }

    /// Sets the initial state of the configuration (with the current torque input): the rigid
    /// motion, the hinge force of its balance of linear momentum, the body's own initial state;
    /// [`Error::NonFinite`] if a quantity of it is NaN or infinite.
    pub(super) fn initialize(&mut self) -> Result<(), Error> {
        let (m, now) = (&self.model, &mut self.now);
        now.state = m.initial_state(now.held_torque);
        now.forget_measures();
        // the branch of the hub angle: the initial angle
        now.theta = m.config.initial.angle_deg.to_radians();
        // The multipliers of the initial state from the balance of linear momentum:
        // −λ = ∫ ρ t a dA − F_gravity  (the force the hinge must exert on the body).
        let mut ma = vec![0.0; now.state.a.len()];
        m.mass.apply(&now.state.a, &mut ma);
        let pendulum = &m.bodies[0];
        let (ma, weight) = (
            &ma[..2 * pendulum.nodes.end],
            pendulum.gravity.load_gradient.iter().sum::<f64>(),
        );
        let fx: f64 = ma.iter().step_by(2).sum();
        let fy: f64 = ma.iter().skip(1).step_by(2).sum::<f64>() + weight;
        now.lambda = [-fx, -fy];
        self.body.initialize(m, now)?;
        let theta0 = m.projection.angle(&now.state.u);
        now.unwrap = Unwrap::starting_at(theta0);
        now.theta = theta0;
        // step 0 by the rule of every step's end (`levels`): no quantity NaN or infinite
        self.check_finite(self.contact.records.len())
    }
}

/// A simulation built by [`Simulation::build`], with what its set-up took.
pub struct Built {
    /// The simulation, at its initial state.
    pub simulation: Simulation,
    /// Wall time of the mesh's generation or reading \[s\].
    pub mesh_seconds: f64,
    /// Wall time of the model's operators and the initial state \[s\].
    pub setup_seconds: f64,
    /// The mesh-size warning ([`crate::mesh::max_size_warning`]), if the mesh is that large.
    pub mesh_warning: Option<String>,
}
