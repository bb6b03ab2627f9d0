//! The full finite-element body: the displacement of every node, advanced by a time scheme of
//! [`crate::scheme`] (its Newton solver and reusable factorisation here), with the initial
//! elastic equilibrium, the rigid-body measures of its fields, and the energies of a state.
//!
//! The energy-momentum scheme's step starts from the elastic terms' start data of its state
//! (`F`, `E` and `ψ(E)` at every quadrature point, [`crate::terms::Term::discrete_start`]); the
//! strain energy of that state is its sum (bit for bit the pass over the fields: the same `ψ` at
//! the same points, summed in the same order), so an output read between two steps costs no pass
//! over the elements of its own. The data is kept with the displacement it was made from and is valid
//! while the state's displacement is that one, bit for bit (whatever changed it: a step, a
//! roll-back, a restore, a new initial state).

mod guess;

use super::interface::{Ask, BodySnapshot, Taken};
use super::measures::Kinematics;
use super::pool::on_pool;
use super::Now;
use crate::config::InitialElastic;
use crate::error::Error;
use crate::error::NewtonError;
use crate::model::{Model, State};
use crate::newton::{NewtonSettings, Solver, Timings};
use crate::scheme::{self, Iterate, Start, TimeScheme, RESIDUAL_TOLERANCE};
use crate::terms::{Inertia, Linear, StepContext, Term};

/// Passes of the proximal-point iteration of the initial equilibrium (see the module doc of
/// [`crate::simulation`]).
const PROXIMAL_PASSES: usize = 4;

/// The full body (see the module doc).
pub(crate) struct Full {
    /// Newton workspace (factorisation, buffers).
    solver: Solver,
    /// The time scheme (`time.scheme`).
    scheme: Box<dyn TimeScheme>,
    /// `(t, α)` at the start of the previous (sub)step, for the predictor's `α̇`.
    previous_alpha: Option<(f64, f64)>,
    /// The elastic terms' start data of a state (one per body) with the displacement it was
    /// made from (see the module doc).
    starts: Option<(Vec<f64>, Vec<Vec<f64>>)>,
    /// `M x` of the current positions (valid with the rates of `Now`).
    mx: Vec<f64>,
}

impl Full {
    /// The full body of `model`: its solver's symbolic analysis and its time scheme.
    pub fn new(model: &Model) -> Result<Self, Error> {
        let rotating = 2 * model.bodies[0].nodes.end;
        Ok(Self {
            solver: Solver::with_bodies(&model.pattern, &model.hinge, model.fixed.clone(), rotating)?,
            scheme: scheme::for_config(&model.config),
            previous_alpha: None,
            starts: None,
            mx: Vec::new(),
        })
    }

    /// Puts the rigid initial state in `now` into elastic equilibrium, if the configuration asks
    /// for it (see the module doc of [`crate::simulation`]).
    pub fn initialize(&mut self, model: &Model, now: &mut Now) -> Result<(), Error> {
        if model.config.initial.elastic_state() != InitialElastic::Equilibrium {
            return Ok(());
        }
        let m = model;
        let mut inertial = vec![0.0; now.state.a.len()];
        m.mass.apply(&now.state.a, &mut inertial);
        let dalembert = Linear::new(inertial);
        let cx = now.context();
        let load_scale = dalembert
            .load_gradient
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
            frame_angle: m.projection.angle(&now.state.u),
            matrix_key: -1.0,
            reuse: false,
            residual_turn: 0.0,
        };
        let mut u = now.state.u.clone();
        let mut lambda = now.lambda;
        // Proximal-point iterations: re-centre the pin on the last solution so that its force,
        // c M (u − u_pin), vanishes in the limit; the elastic modes converge by the factor
        // c M / K per pass (about 1e-6 for steel), the rotation stays pinned.
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
        now.state.u = u;
        now.lambda = lambda;
        now.forget_measures();
        Ok(())
    }

    /// One step of `dt` (see [`super::dynamics::Dynamics::step`]): the guess, the scheme's solve,
    /// and on success the new state with the torque's work over the step.
    pub fn step(&mut self, model: &Model, now: &mut Now, dt: f64, ask: &Ask) -> Result<Taken, NewtonError> {
        let rates = (now.state.t, self.kinematics_of(model, now, ask.step).alpha);
        // inside a chattering impact, the extrapolation of its alternation, with a fresh tangent;
        // not where it would invert an element (a soft head crushed against the wall, after a
        // cut-back), where the rigid turn of the current state serves. (Impacts are resolved in
        // sub-steps only with the energy-momentum scheme, `config::wall`.)
        let chatter = ask
            .impact
            .and_then(|trail| self.chatter_guess(model, now, trail, dt))
            .filter(|guess| {
                let cx = StepContext::at(guess, now.state.t + dt, now.theta, now.held_torque);
                model.strain_energy(guess, &cx).is_finite()
            });
        let fresh_tangent = chatter.is_some();
        let guess = match chatter {
            Some(guess) => guess,
            None => self.rotational_guess(model, now, dt, ask),
        };
        let load_scale = self.load_scale(model, now, now.state.t + dt, ask.step);
        let kinetic = self.kinematics_of(model, now, ask.step).kinetic;
        if self.scheme.uses_elastic_starts() {
            self.elastic_starts(model, now);
        }
        let elastic = match &self.starts {
            Some((_, data)) if self.scheme.uses_elastic_starts() => data.as_slice(),
            _ => &[],
        };
        let start = Start {
            model,
            state: &now.state,
            lambda: now.lambda,
            theta: now.theta,
            held_torque: now.held_torque,
            load_scale,
            kinetic,
            elastic,
        };
        let iterate = Iterate {
            correct: ask.correct,
            fresh_tangent,
        };
        let stepped = self.scheme.step(&start, dt, guess, &mut self.solver, iterate)?;
        self.previous_alpha = Some(rates);
        now.forget_measures();
        let old = &now.state;
        let cx = StepContext {
            t: stepped.state.t,
            t0: old.t,
            dt,
            u0: &old.u,
            theta0: now.theta,
            torque: now.held_torque,
        };
        now.torque_work += model
            .loads()
            .map(|term| term.external_work(&stepped.state.u, &cx))
            .sum::<f64>();
        now.state = stepped.state;
        now.lambda = stepped.lambda;
        // the branch of θ for the next (sub)step's context
        now.theta = now.unwrap.next(model.projection.angle(&now.state.u));
        Ok(Taken {
            iterations: stepped.iterations,
            factorizations: stepped.factorizations,
        })
    }

    /// See [`super::dynamics::Dynamics::retries_uncorrected`].
    pub fn retries_uncorrected(&self) -> bool {
        self.scheme.retries_uncorrected()
    }

    /// Makes, after an output step, what the next step starts from and what the outputs read
    /// between two steps: the elastic start data and the rigid-body measures, side by side on the
    /// pool (the one's mass products beside the other's pass over the elements).
    pub fn after_output_step(&mut self, model: &Model, now: &mut Now, step: usize) {
        if !self.scheme.uses_elastic_starts() {
            return;
        }
        if self.current_starts(now).is_some() || now.rates.is_some() {
            self.elastic_starts(model, now);
            self.kinematics_of(model, now, step);
            return;
        }
        let cx = now.context();
        let mean = self.scheme.keeps_mean_acceleration();
        let (starts, (k, mx)) = rayon::join(|| starts_of(model, &cx), || measure(mean, model, &cx, step, &now.state));
        self.starts = Some((now.state.u.clone(), starts));
        (now.rates, self.mx) = (Some(k), mx);
    }

    /// Makes the elastic start data of the current state if the scheme reads it and it is not
    /// made yet (the strain energy is its sum), on the pool.
    pub fn prepare_energies(&mut self, model: &Model, now: &Now) {
        if self.scheme.uses_elastic_starts() && self.current_starts(now).is_none() {
            on_pool(|| self.elastic_starts(model, now));
        }
    }

    /// `[strain, gravity, contact]` energy of the current state \[J\].
    pub fn energies(&self, model: &Model, now: &Now) -> [f64; 3] {
        let (m, u) = (model, &now.state.u);
        let cx = now.context();
        let strain = match self.current_starts(now) {
            Some(starts) => m
                .bodies
                .iter()
                .zip(starts)
                .map(|(b, d)| b.elastic.energy_of_start(d))
                .sum(),
            None => m.strain_energy(u, &cx),
        };
        [strain, m.gravity_energy(u, &cx), m.contact_energy(u, &cx)]
    }

    /// The rigid-body measures of the current state.
    pub fn kinematics(&mut self, model: &Model, now: &Now, step: usize) -> Kinematics {
        let mean = self.scheme.keeps_mean_acceleration();
        let (k, mx) = measure(mean, model, &now.context(), step, &now.state);
        self.mx = mx;
        k
    }

    /// [`Full::kinematics`] through the cache of `now`.
    fn kinematics_of(&mut self, model: &Model, now: &mut Now, step: usize) -> Kinematics {
        if let Some(k) = now.rates {
            return k;
        }
        let k = self.kinematics(model, now, step);
        now.rates = Some(k);
        k
    }

    /// The largest nodal applied force: gravity, the inertia force `M a` of the current state, and
    /// for the actuator torque at time `t` the largest nodal inertia force of the rigid angular
    /// acceleration it drives, `|M(t)|/I · max_a |(M_mass (e_z × x))_a|` \[N\]. (The torque's own
    /// nodal forces sit on the short hinge edge and are about a hundred times the nodal gravity
    /// forces; as a scale they would loosen the residual check for the whole body.)
    pub fn load_scale(&mut self, model: &Model, now: &mut Now, t: f64, step: usize) -> f64 {
        let inertia = self.kinematics_of(model, now, step).inertia_force;
        let m = model;
        let gravity = m.largest_gravity_force();
        let torque = m.applied_torque(t, now.held_torque).abs();
        let mut driven = 0.0;
        if torque > 0.0 {
            // M (e_z × x) = e_z × (M x): the nodal inertia forces of a unit angular acceleration
            let largest = self.mx.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            driven = torque / m.inertia_pivot() * largest;
        }
        (inertia + gravity + driven).max(1e-12)
    }

    /// Makes the elastic start data of the current state unless it is made already.
    fn elastic_starts(&mut self, model: &Model, now: &Now) {
        if self.current_starts(now).is_none() {
            let data = starts_of(model, &now.context());
            self.starts = Some((now.state.u.clone(), data));
        }
    }

    /// The elastic start data if it is that of the current state.
    fn current_starts(&self, now: &Now) -> Option<&[Vec<f64>]> {
        let (u, data) = self.starts.as_ref()?;
        let s = &now.state.u;
        let same = u.len() == s.len() && u.iter().zip(s).all(|(a, b)| a.to_bits() == b.to_bits());
        same.then_some(data.as_slice())
    }

    /// The body's part of a snapshot: the predictor's previous rate and the solver's reusable
    /// factorisation.
    pub fn save(&self) -> BodySnapshot {
        BodySnapshot {
            previous_alpha: self.previous_alpha,
            factor: self.solver.factor_state(),
            reduced: None,
        }
    }

    /// Returns to a snapshot's part. The matrix was factorised before with this symbolic
    /// analysis; should that fail now, the next step factorises afresh.
    pub fn restore(&mut self, model: &Model, s: &BodySnapshot) {
        self.previous_alpha = s.previous_alpha;
        if self.solver.restore_factor(&model.pattern, s.factor.clone()).is_err() {
            let _ = self.solver.restore_factor(&model.pattern, None);
        }
    }

    /// Accumulated Newton timings.
    pub fn timings(&self) -> Timings {
        self.solver.timings
    }

    /// Nonzeros of the factor.
    pub fn factor_nnz(&self) -> usize {
        self.solver.factor_nnz()
    }
}

/// Every body's elastic start data at the state of `cx` ([`Term::discrete_start`]).
fn starts_of(m: &Model, cx: &StepContext) -> Vec<Vec<f64>> {
    m.bodies.iter().map(|b| b.elastic.discrete_start(cx)).collect()
}

/// The rigid-body measures of the state `s` at the context `cx` of that state, after `step`
/// steps, and `M x`, with `mean` whether the scheme keeps the step's mean acceleration in `s.a`: a function of the state alone, so that a step can make it beside the
/// next step's start data. With `m_x = M x` for the positions `x = X + u`:
/// `∫ ρ t |x|² dA = x·m_x`, and since `M` is symmetric and acts on both components alike,
/// `Σ_ab M_ab x_a × w_b = Σ_b (m_x)_b × w_b` for any field `w`: one mass product serves the
/// angular velocity, the angular momentum and the angular acceleration; a second one (`M v`)
/// the kinetic energy.
fn measure(mean: bool, m: &Model, cx: &StepContext, step: usize, s: &State) -> (Kinematics, Vec<f64>) {
    // the pendulum's positions (zeros at the other bodies' nodes: the rigid-body measures are
    // the pendulum's; the mass matrix couples no two bodies, so M x stays the pendulum's)
    let mut x = m.positions(&s.u);
    x[2 * m.bodies[0].nodes.end..].iter_mut().for_each(|c| *c = 0.0);
    // M x, M v and M a (for the load scale of the next step) in one pass over the matrix
    let (mut mx, mut mv, mut ma) = (vec![0.0; x.len()], vec![0.0; x.len()], vec![0.0; x.len()]);
    m.mass.apply_each([&x, &s.v, &s.a], [&mut mx, &mut mv, &mut ma]);
    let cross = |w: &[f64]| -> f64 {
        (0..x.len() / 2)
            .map(|b| mx[2 * b] * w[2 * b + 1] - mx[2 * b + 1] * w[2 * b])
            .sum()
    };
    let polar: f64 = x.iter().zip(&mx).map(|(a, b)| a * b).sum();
    let momentum = cross(&s.v);
    let alpha = if mean && step > 0 {
        // the consistent end-of-step value: the moment of the external loads at x (the strain
        // energy's forces and the hinge force have none) over the polar moment of inertia
        let mut loads = vec![0.0; x.len()];
        m.bodies[0].gravity.add_gradient(&s.u, cx, &mut loads);
        for term in m.loads() {
            term.add_gradient(&s.u, cx, &mut loads);
        }
        let moment: f64 = (0..x.len() / 2)
            .map(|a| x[2 * a + 1] * loads[2 * a] - x[2 * a] * loads[2 * a + 1])
            .sum();
        moment / polar
    } else {
        cross(&s.a) / polar
    };
    let kinetic = 0.5 * s.v.iter().zip(&mv).map(|(a, b)| a * b).sum::<f64>();
    let k = Kinematics {
        omega: momentum / polar,
        alpha,
        kinetic,
        momentum,
        inertia_force: ma.iter().fold(0.0f64, |a, b| a.max(b.abs())),
    };
    (k, mx)
}

#[cfg(test)]
mod tests {
    use super::super::{Dynamics, Simulation};
    use crate::config::Config;

    #[test]
    fn the_strain_energy_from_the_start_data_is_the_pass_over_the_fields_bit_for_bit() {
        let config = Config::default();
        let mut sim = Simulation::build(&config).unwrap().simulation;
        for _ in 0..3 {
            sim.step(config.time.dt).unwrap();
            let Dynamics::Full(body) = &sim.body else {
                panic!("the default body is the full one")
            };
            assert!(body.current_starts(&sim.now).is_some(), "a step leaves its start data");
            let from_starts = body.energies(&sim.model, &sim.now)[0];
            let from_fields = sim.model.strain_energy(&sim.now.state.u, &sim.now.context());
            assert_eq!(
                from_starts.to_bits(),
                from_fields.to_bits(),
                "{from_starts:e} {from_fields:e}"
            );
        }
    }
}
