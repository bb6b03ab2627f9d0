//! Setting up a [`Simulation`]: the solver's symbolic analysis, the initial state of the
//! configuration, the hinge force of its rigid motion and the initial elastic equilibrium
//! (the equations are in the module doc of [`crate::simulation`]).

use super::{impact, Clock, Model, Simulation, RESIDUAL_TOLERANCE};
use crate::config::{Config, InitialElastic};
use crate::newton::{NewtonSettings, Solver};
use crate::rigid::Unwrap;
use crate::terms::{Inertia, Linear, StepContext, Term};
use crate::{Error, Mesh};

/// Passes of the proximal-point iteration of the initial equilibrium (see [`Simulation`]'s set-up).
const PROXIMAL_PASSES: usize = 4;

impl Simulation {
    /// Sets up the run: operators, symbolic factorisation (for the full model; a reduced body's
    /// solver makes it only if it ever factorises), initial state.
    pub fn new(model: Model) -> Result<Self, Error> {
        let (pattern, hinge, fixed, rotating) = (
            &model.pattern,
            &model.hinge,
            model.fixed.clone(),
            2 * model.bodies[0].nodes.end,
        );
        // a reduced body never factorises the full tangent in its steps
        let solver = match model.reduced {
            Some(_) => Solver::deferred(pattern, hinge, fixed, rotating),
            None => Solver::with_bodies(pattern, hinge, fixed, rotating)?,
        };
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
            previous_alpha: None,
            rates: None,
            mx: Vec::new(),
            starts: None,
            mass_solver: None,
            reduced: None,
            validity: Default::default(),
            stress_reference: Default::default(),
            pending_warning: None,
            fields_stale: false,
            lazy_fields: Default::default(),
            model,
        };
        sim.initialize()?;
        Ok(sim)
    }

    /// Sets the initial state of the configuration (with the current torque input): the rigid
    /// motion, the hinge force of its balance of linear momentum, the elastic equilibrium.
    pub(super) fn initialize(&mut self) -> Result<(), Error> {
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
        if sim.model.reduced.is_some() {
            sim.initialize_reduced();
        } else if sim.model.config.initial.elastic_state() == InitialElastic::Equilibrium {
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
