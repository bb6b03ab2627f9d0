//! The stepping interface of [`Simulation`]: the one way to advance a simulation, used by the CLI
//! and by programs that drive the pendulum step by step (a controller, a co-simulation master).
//!
//! * [`Simulation::step`] advances by any positive `dt` (sub-steps and cut-backs inside, as
//!   [`Simulation::advance`] describes). Over a run of steps with the same `dt` the time is
//!   `t_start + n · dt`, computed rather than accumulated, so `n` calls of `step(time.dt)` from the
//!   start are bit for bit the fixed-step run. Any other `dt` starts a new run at the time
//!   reached; time is never rounded to a grid. [`Simulation::step_to`] lands exactly on a time.
//! * **A failed step changes nothing.** When a step fails after its cut-backs, everything that
//!   determines later steps is put back as it was before the call (fields, multipliers, counters,
//!   the unwrapping branch of θ, the previous α, the torque's work, the held torque, and the solver's reusable factorisation), and the error is returned: calling
//!   again with a smaller `dt` is the same as having called with it in the first place.
//! * **Inputs held between steps**: [`Simulation::set_torque`] replaces the `[torque]` profile by a
//!   value held until it is set again (a zero-order hold: the step uses it from its start to its end).
//! * **Outputs on request**: [`Simulation::time`], [`Simulation::theta`],
//!   [`Simulation::angular_rates`], [`Simulation::energies`], [`Simulation::hinge_reaction`],
//!   [`Simulation::von_mises_max`], [`Simulation::last_newton_iterations`]; the fields
//!   [`Simulation::displacement`], [`Simulation::velocity`], [`Simulation::acceleration_field`],
//!   [`Simulation::nodal_stress`]. A step computes none of the stresses; they cost a pass over every
//!   element node and are made only when asked for.

use super::pool::on_pool;
use super::{Clock, Simulation, StepRecord};
use crate::constraint::Hinge;
use crate::post::NodalStress;
use crate::Error;

/// The energies of the current state \[J\].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// Kinetic energy.
    pub kinetic: f64,
    /// Strain energy.
    pub strain: f64,
    /// Gravitational energy relative to the pivot height.
    pub gravity: f64,
    /// Contact energy (0 without a wall).
    pub contact: f64,
    /// `kinetic + strain + gravity + contact`.
    pub total: f64,
    /// Work done by the torque since the start (not part of `total`: `total − total(0)` equals it up
    /// to the integrator's energy error).
    pub torque_work: f64,
}

impl Simulation {
    /// Advances the state by `dt` \[s\] (any finite `dt > 0`) and returns the Newton iterations of
    /// the step. On failure the state is exactly as before the call (see the module doc) and the
    /// error ([`Error::TimeStep`]) is returned; `dt` out of range is [`Error::Input`].
    pub fn step(&mut self, dt: f64) -> Result<usize, Error> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::Input(format!(
                "step(dt = {dt} s) at t = {} s: allowed dt > 0 and finite",
                self.state.t
            )));
        }
        let clock = self.clock.after(dt);
        self.step_with(dt, clock)
    }

    /// Advances the state by one step to exactly `t_end` \[s\] (after the current time), for a last
    /// step that lands on an end time; otherwise as [`Simulation::step`].
    pub fn step_to(&mut self, t_end: f64) -> Result<usize, Error> {
        let t0 = self.state.t;
        let dt = t_end - t0;
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::Input(format!(
                "step_to(t_end = {t_end} s) from t = {t0} s: the end must lie after the current time"
            )));
        }
        self.step_with(dt, Clock::at(t_end))
    }

    /// Shorthand for [`Simulation::step`] of `time.dt` followed by [`Simulation::record`] (with the
    /// nodal stresses of [`StepRecord::von_mises_max`]): the one stepping path, with its record.
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

    /// One step of `dt` to the time of `clock` (see [`Simulation::step`]).
    ///
    /// The step runs on a thread of the pool that computes its elements (rayon's): called from
    /// elsewhere (the CLI's main thread, an FMU master's, Python's), it is handed to the pool for
    /// its duration. From outside, each parallel pass over the elements (several per step) would
    /// wake the pool's threads and put the caller to sleep until they finish; on a worker, the
    /// caller computes its share and only the other threads are woken. The arithmetic is the same,
    /// so are the results, bit for bit. Measured on 2 cores, the default pendulum at dt = 1 ms:
    /// 1.43–1.50 ms per step from outside, 1.23 ms on a worker (`examples/stepper_speed.rs`).
    ///
    /// A reduced body's step has no pass over the elements to share (7 µs in all, less than the
    /// hand-over itself): it runs on the caller's thread.
    fn step_with(&mut self, dt: f64, clock: Clock) -> Result<usize, Error> {
        if self.model.reduced.is_some() {
            return self.step_on_worker(dt, clock);
        }
        on_pool(|| self.step_on_worker(dt, clock))
    }

    /// [`Simulation::step_with`] on a thread of the pool.
    fn step_on_worker(&mut self, dt: f64, clock: Clock) -> Result<usize, Error> {
        let before = self.rollback_point();
        match self.advance_over(dt) {
            Ok(its) => {
                self.clock = clock;
                self.state.t = clock.time();
                self.theta = self.unwrap.next(self.proxy_angle());
                self.last_iterations = its;
                if self.model.scheme == crate::config::Scheme::EnergyMomentum && self.model.reduced.is_none() {
                    // what the next step starts from, made here on the pool: the outputs read
                    // between two steps (the strain energy, ω and α) then cost no pass of their own
                    self.prepare_next_step();
                }
                Ok(its)
            }
            Err(e) => {
                self.roll_back(&before);
                Err(self.outside_model(e, dt))
            }
        }
    }

    /// A failed step's error, or the cause outside the model that explains it: the head's rigid
    /// flight over the step (from the rolled-back start, at the best-fit rates, in eighths) came
    /// round the deformable wall's face ([`crate::terms::WallContact::behind_face`]).
    fn outside_model(&mut self, e: Error, dt: f64) -> Error {
        let Error::TimeStep { step, t, .. } = e else {
            return e;
        };
        let (omega, alpha) = self.angular_rates();
        let Some(wall) = &self.model.wall else {
            return e;
        };
        (1..=8)
            .map(|k| dt * k as f64 / 8.0)
            .find_map(|h| wall.behind_face(&self.state.u, omega * h + 0.5 * alpha * h * h))
            .map_or(e, |message| Error::OutsideModel { step, t, message })
    }

    /// Holds the actuator torque at `value` \[N m\] from now on, replacing the `[torque]` profile
    /// (a co-simulation input; it stays until set again). The torque term must exist: a model built
    /// with `torque.profile = "none"` has none (so that the default run is unchanged) and this is an
    /// error naming the key; declare a torque input with `profile = "constant"`, `amplitude = 0`.
    /// Before the first step the initial state is set up again with the held torque (its rigid
    /// acceleration `α₀` and the elastic equilibrium include it), exactly as with a configured
    /// constant torque of that value. A torque beyond the hub's limit is refused as
    /// [`Error::Input`] ([`crate::terms::Torque::check_input`]), as a configured one is at set-up.
    pub fn set_torque(&mut self, value: f64) -> Result<(), Error> {
        if !value.is_finite() {
            return Err(Error::Input(format!(
                "set_torque({value} N m): allowed a finite torque"
            )));
        }
        let Some(torque) = &self.model.torque else {
            return Err(Error::Config(
                "set_torque: this model has no torque term (torque.profile = \"none\"); set torque.profile = \
                 \"constant\" with torque.amplitude = 0 to declare a torque input"
                    .into(),
            ));
        };
        let c = &self.model.config;
        torque.check_input(value, c.geometry.thickness, c.material.youngs_modulus)?;
        let before = (self.step == 0).then(|| self.rollback_point());
        self.apply_torque_input(Some(value));
        self.rates = None;
        if let Some(before) = before {
            // an input set before the first step is part of the initial state (its rigid
            // acceleration and elastic equilibrium), as a configured torque would be; if that
            // equilibrium fails, nothing has changed
            if let Err(e) = self.initialize() {
                self.roll_back(&before);
                return Err(e);
            }
        }
        Ok(())
    }

    /// The torque held by [`Simulation::set_torque`] \[N m\], `None` while the profile acts.
    pub fn held_torque(&self) -> Option<f64> {
        self.held_torque
    }

    /// Makes the torque follow `held` (a value) or the configured profile (`None`): the held input
    /// reaches the terms through their [`crate::terms::StepContext`].
    pub(super) fn apply_torque_input(&mut self, held: Option<f64>) {
        self.held_torque = held;
    }

    /// Time of the current state \[s\].
    pub fn time(&self) -> f64 {
        self.state.t
    }

    /// Proxy angle of the current state, unwrapped (continuous past ±π) \[rad\].
    pub fn theta(&self) -> f64 {
        self.theta
    }

    /// Newton iterations (linear solves) of the last step: its sub-steps, and the attempts that
    /// failed and were halved (0 before the first step).
    pub fn last_newton_iterations(&self) -> usize {
        self.last_iterations
    }

    /// Kinetic, strain and gravitational energy of the current state and the torque's work \[J\].
    pub fn energies(&mut self) -> Energies {
        let kinetic = self.kinematics().kinetic;
        let full = self.model.scheme == crate::config::Scheme::EnergyMomentum && self.model.reduced.is_none();
        if full && self.current_starts().is_none() {
            // the next step needs the start data anyway; the strain energy is its sum (a step
            // makes it at its end, so only a state set otherwise needs it made here)
            on_pool(|| self.elastic_starts());
        }
        self.energies_with(kinetic)
    }

    /// The energies of the current state with its kinetic energy \[J\] already computed: the one
    /// definition of the total energy, for [`Simulation::energies`] and the records.
    pub(super) fn energies_with(&self, kinetic: f64) -> Energies {
        let cx = self.context();
        let (s, m) = (&self.state, &self.model);
        let (strain, gravity, contact) = match (&m.reduced, &self.reduced, &m.reduced_wall) {
            // the deformable wall: the block's modal strain energy, its weight and the contact
            // from the fields, which every step with a wall brings up to date
            (Some(body), Some(r), Some(wall)) => (
                body.strain(&r.q) + wall.strain(&r.wall_q),
                body.gravity(r, m.config.gravity.g) + crate::terms::Term::energy(&*m.bodies[1].gravity, &s.u, &cx),
                if self.reduced_clearance().is_some_and(|c| c > 0.0) {
                    0.0
                } else {
                    m.contact_energy(&s.u, &cx)
                },
            ),
            (Some(body), Some(r), None) => (
                body.strain(&r.q),
                body.gravity(r, m.config.gravity.g),
                m.wall.as_ref().map_or(0.0, |w| body.contact(r, w).0),
            ),
            _ => (
                match self.current_starts() {
                    Some(starts) => m
                        .bodies
                        .iter()
                        .zip(starts)
                        .map(|(b, d)| b.elastic.energy_of_start(d))
                        .sum(),
                    None => m.strain_energy(&s.u, &cx),
                },
                m.gravity_energy(&s.u, &cx),
                m.contact_energy(&s.u, &cx),
            ),
        };
        Energies {
            kinetic,
            strain,
            gravity,
            contact,
            total: kinetic + strain + gravity + contact,
            torque_work: self.torque_work,
        }
    }

    /// The gap of the current state \[m\], positive while apart: with a wall, the smallest gap of
    /// the head's arc to its face (negative: the largest penetration; the `gap_m` column of
    /// `results.csv`); without one, the smallest signed distance of the arc's nodes to the plane
    /// `x = wall.x` (`+∞` for a mesh without the arc).
    pub fn gap(&self) -> f64 {
        if let (Some(body), Some(r), Some(wall), None) = (
            &self.model.reduced,
            &self.reduced,
            &self.model.wall,
            &self.model.reduced_wall,
        ) {
            return body.contact(r, wall).1;
        }
        let u = &self.state.u;
        if let Some(wall) = &self.model.wall {
            return wall.smallest_gap(u);
        }
        let (mesh, face_x) = (&self.model.mesh, self.model.config.wall.x);
        mesh.edges_named(super::CONTACT_BOUNDARY)
            .flat_map(|e| e.nodes)
            .map(|n| mesh.nodes[n][0] + u[2 * n] - face_x)
            .fold(f64::INFINITY, f64::min)
    }

    /// The normal force of the wall on the head in the current state \[N\] (the `contact_force_N`
    /// column of `results.csv`, a negative zero as 0); 0 without a wall. The one reading of the
    /// contact force for the FMU's and the Python package's outputs.
    pub fn contact_force(&self) -> f64 {
        if let (Some(body), Some(r), Some(wall), None) = (
            &self.model.reduced,
            &self.reduced,
            &self.model.wall,
            &self.model.reduced_wall,
        ) {
            return crate::post::unsigned_zero(body.contact(r, wall).2);
        }
        if self.reduced_clearance().is_some_and(|c| c > 0.0) {
            return 0.0;
        }
        self.model
            .wall
            .as_ref()
            .map_or(0.0, |wall| crate::post::unsigned_zero(wall.normal_force(&self.state.u)))
    }

    /// Force of the hinge on the body \[N\].
    pub fn hinge_reaction(&self) -> [f64; 2] {
        Hinge::reaction(self.lambda)
    }

    /// Nodal displacement, interleaved `[u_x, u_y]` per node \[m\].
    pub fn displacement(&self) -> &[f64] {
        self.lazy_fields().map_or(&self.state.u, |f| &f[0])
    }

    /// Nodal velocity, interleaved \[m/s\].
    pub fn velocity(&self) -> &[f64] {
        self.lazy_fields().map_or(&self.state.v, |f| &f[1])
    }

    /// Nodal Cauchy and von Mises stresses of the current state (computed on this call).
    pub fn nodal_stress(&mut self) -> NodalStress {
        self.stress_evaluations += 1;
        if let (Some(body), Some(r)) = (&self.model.reduced, &self.reduced) {
            return body.nodal_stress(r);
        }
        self.model.nodal_stress(&self.state.u)
    }

    /// The largest nodal von Mises stress of the current state \[Pa\] (computed on this call).
    pub fn von_mises_max(&mut self) -> f64 {
        self.stress_evaluations += 1;
        if let (Some(body), Some(r)) = (&self.model.reduced, &self.reduced) {
            return body.von_mises_max(r, &mut self.stress_reference);
        }
        self.model.max_von_mises(&self.state.u)
    }

    /// How often nodal stresses were computed so far (by [`Simulation::nodal_stress`],
    /// [`Simulation::von_mises_max`], records and frames; never by a step).
    pub fn stress_evaluations(&self) -> usize {
        self.stress_evaluations
    }
}
