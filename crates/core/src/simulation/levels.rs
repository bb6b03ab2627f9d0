//! The levels of a step, from the top: the **output step** of length `Δt` (its clock, θ, the
//! check that every quantity of the state it reached is finite, the roll-back of a failure), its **impact resolution** (`impact`) or its split into equal
//! **sub-steps** by the predicted rotation, and each sub-step's **attempts**: the body's step,
//! halved on failure as `solver.max_cutbacks` allows ([`crate::config::Cutbacks`]).
//!
//! A step whose predicted rotation `|ω| Δt + ½ |α| Δt²` exceeds the scheme's largest turn
//! ([`crate::scheme::largest_turn`]) is split into 2, 4, 8, … equal sub-steps (powers of two, so
//! the sub-step changes rarely).
//!
//! **Why a halved interval's second half starts at the depth its first half ended at**, and not
//! with an attempt at its own length: a failed attempt runs out of Newton iterations (up to
//! `solver.max_iterations`, and at the last depth a second attempt without the GMRES correction),
//! many times the cost of an attempt that converges. Where a local event needs sub-steps several
//! halvings down, retrying every level on the way back up would make one failed attempt per
//! sub-step; starting where the first half ended makes one per level. The next output step starts
//! again at its full length.

use super::pool::on_pool;
use super::{Clock, Simulation, StepRecord};
use crate::error::Error;
use crate::error::NewtonError;

impl Simulation {
    /// The output step of `dt` to the time of `clock` (see [`Simulation::step`]): on success the
    /// clock, θ's branch and what the next step starts from; on failure everything as before.
    ///
    /// The full body's step runs on a thread of the pool that computes its elements (rayon's):
    /// called from elsewhere (the CLI's main thread, an FMU master's, Python's), it is handed to
    /// the pool for its duration, so that each parallel pass over the elements does not wake the
    /// pool's threads and put the caller to sleep until they finish; on a worker, the caller
    /// computes its share. The arithmetic is the same, so are the results, bit for bit. A reduced
    /// step has no pass over the elements to share and runs on the caller's thread.
    pub(super) fn output_step(&mut self, dt: f64, clock: Clock) -> Result<usize, Error> {
        if self.body.steps_on_pool() {
            on_pool(|| self.output_step_here(dt, clock))
        } else {
            self.output_step_here(dt, clock)
        }
    }

    /// [`Simulation::output_step`] on the calling thread.
    fn output_step_here(&mut self, dt: f64, clock: Clock) -> Result<usize, Error> {
        let before = self.rollback_point();
        let records = self.contact.records.len();
        match self.substeps(dt) {
            Ok(its) => {
                self.clock = clock;
                self.now.state.t = clock.time();
                self.now.theta = self.now.unwrap.next(self.body.proxy_angle(&self.model, &self.now));
                self.last_iterations = its;
                // what the next step starts from, made here (on the pool): the outputs read
                // between two steps then cost no pass of their own
                self.body.after_output_step(&self.model, &mut self.now, self.step);
                if let Err(e) = self.check_finite(records) {
                    self.roll_back(&before);
                    return Err(e);
                }
                Ok(its)
            }
            Err(e) => {
                self.roll_back(&before);
                Err(self.outside_model(e, dt))
            }
        }
    }

    /// The state an output step reached, checked by the rule of [`StepRecord::check_finite`]:
    /// the records of the sub-steps it took inside impacts (from `records` on), then its own
    /// record without the nodal stresses (a step computes none; the run driver checks the
    /// records it writes, stresses included). Its rates and energies are what the next step and
    /// the outputs read anyway.
    pub(super) fn check_finite(&mut self, records: usize) -> Result<(), Error> {
        self.contact.records[records..]
            .iter()
            .try_for_each(StepRecord::check_finite)?;
        self.record_without_stress(self.last_iterations).check_finite()
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
            .find_map(|h| wall.behind_face(&self.now.state.u, omega * h + 0.5 * alpha * h * h))
            .map_or(e, |message| Error::OutsideModel { step, t, message })
    }

    /// The output step of `dt` in sub-steps: resolving impacts (`impact`), or split by the
    /// predicted rotation (see the module doc); counts the step; returns the Newton iterations.
    fn substeps(&mut self, dt: f64) -> Result<usize, Error> {
        let t0 = self.now.state.t;
        let (omega, alpha) = self.angular_rates();
        let turn = omega.abs() * dt + 0.5 * alpha.abs() * dt * dt;
        let limit = crate::scheme::largest_turn(&self.model.config);
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
            its = self.resolve_impacts(dt)?;
        } else {
            for _ in 0..substeps {
                let u0 = self.model.wall.is_some().then(|| self.now.state.u.clone());
                its += self.substep(h).map_err(failed(self.step + 1))?;
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

    /// One sub-step of `dt`, halved on failure; returns the Newton iterations used, or the failure
    /// and the length of the shortest attempt.
    pub(super) fn substep(&mut self, dt: f64) -> Result<usize, (NewtonError, f64)> {
        self.attempt(dt, 0, 0).map(|(its, _)| its)
    }

    /// The interval `dt` at cut-back depth `depth` (halved that many times), split without an
    /// attempt down to `start` (the depth the sub-step before it was taken at; see the module
    /// doc); returns the Newton iterations (those of the attempts that failed and were halved
    /// included) and the depth of its last sub-step.
    fn attempt(&mut self, dt: f64, depth: usize, start: usize) -> Result<(usize, usize), (NewtonError, f64)> {
        // the iterations of the attempts at this interval that failed
        let mut failed = 0;
        if depth >= start {
            let mut attempt = self.body_step(dt, true);
            // asked only on a failure: the wave time goes over every element
            let halvable = attempt.is_err()
                && self
                    .model
                    .config
                    .solver
                    .max_cutbacks
                    .allows(depth, dt, self.model.wave_time());
            // where no halving is left, the step is tried once more without the GMRES correction
            if let Err(e) = &attempt {
                if !halvable && self.body.retries_uncorrected() {
                    failed = e.iterations();
                    attempt = self.body_step(dt, false);
                }
            }
            match attempt {
                Ok(its) => return Ok((failed + its, depth)),
                Err(e) if halvable => {
                    self.cutbacks += 1;
                    failed = e.iterations();
                }
                Err(e) => return Err((e, dt)),
            }
        }
        let (a, last) = self.attempt(0.5 * dt, depth + 1, start)?;
        let (b, last) = self.attempt(0.5 * dt, depth + 1, last)?;
        Ok((failed + a + b, last))
    }

    /// The body's step of `dt` from the current state (`correct`: whether Newton may correct slow
    /// iterations by GMRES); on failure nothing changed.
    fn body_step(&mut self, dt: f64, correct: bool) -> Result<usize, NewtonError> {
        let ask = self.contact.ask(correct, self.step, self.last_iterations);
        let taken = self.body.step(&self.model, &mut self.now, dt, &ask)?;
        self.total_factorizations += taken.factorizations;
        Ok(taken.iterations)
    }
}

#[cfg(test)]
mod tests {
    use crate::config::{Config, InitialAcceleration};
    use crate::error::Error;
    use crate::simulation::Simulation;

    #[test]
    fn a_step_to_a_state_with_an_infinite_quantity_fails_naming_it_and_changes_nothing() {
        let config = Config::default();
        let dt = config.time.dt;
        let mut sim = Simulation::build(&config).unwrap().simulation;
        sim.step(dt).unwrap();
        // the torque's work is summed over the steps and read by none of their equations: an
        // infinite one reaches the next state as it is, and the step then refuses that state
        sim.now.torque_work = f64::INFINITY;
        let before = sim.snapshot();
        match sim.step(dt) {
            Err(Error::NonFinite {
                step: 2,
                t,
                quantity: "torque's work",
                value,
            }) if t == 2.0 * dt && value == f64::INFINITY => {}
            other => panic!("{other:?}"),
        }
        assert!(sim.snapshot() == before, "the refused step changed the state");
    }

    #[test]
    fn an_initial_state_with_a_nan_is_refused_at_the_set_up_as_step_0() {
        let mut config = Config::default();
        // finite, so the configuration is valid; squared in the kinetic energy, it is not
        config.initial.angular_velocity = 1e200;
        config.initial.acceleration = InitialAcceleration::Zero;
        match Simulation::build(&config).map(|_| ()) {
            Err(Error::NonFinite {
                step: 0,
                t: 0.0,
                quantity: "kinetic energy",
                value,
            }) if value.is_nan() => {}
            other => panic!("{other:?}"),
        }
    }
}
