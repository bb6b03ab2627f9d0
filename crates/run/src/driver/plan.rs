//! The steps of a run along its plan ([`PlanSteps`]).

use pendulum_fem_core::config::{StepPlan, Time};
use pendulum_fem_core::simulation::{Simulation, StepRecord};
use pendulum_fem_core::Error;

use super::RunEnd;

/// The steps of a run along a [`StepPlan`]: step `first + i` of the simulation is the plan's
/// `i`-th, of `dt` while `i < plan.full`, else the shortened last one that lands on `end`. The
/// one rule of the driver's runs (restarted ones too) and the Python package's `run`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanSteps {
    /// The plan.
    pub plan: StepPlan,
    dt: f64,
    end: f64,
    first: usize,
}

impl PlanSteps {
    /// The steps of a run of `time` from step 0 at time 0 (a restarted run too: its steps keep
    /// their numbers).
    pub fn of(time: &Time) -> Self {
        Self {
            plan: StepPlan::of(time),
            dt: time.dt,
            end: time.end,
            first: 0,
        }
    }

    /// The steps from the state of `sim` now to the time `end` \[s\] in steps of `dt`.
    pub fn from_now(sim: &Simulation, dt: f64, end: f64) -> Self {
        let time = Time {
            dt,
            end: end - sim.time(),
            ..Time::default()
        };
        Self {
            plan: StepPlan::of(&time),
            dt,
            end,
            first: sim.step,
        }
    }

    /// Whether `sim` has taken every step of the plan.
    pub fn done(&self, sim: &Simulation) -> bool {
        sim.step >= self.first + self.plan.steps()
    }

    /// Takes the next step of the plan; returns its Newton iterations.
    pub fn take(&self, sim: &mut Simulation) -> Result<usize, Error> {
        match sim.step < self.first + self.plan.full {
            true => sim.step(self.dt),
            false => sim.step_to(self.end),
        }
    }

    /// Walks `sim` along the plan: hands the record of the state now, then that of every step, to
    /// `take`, and ends after the plan's last step ([`RunEnd::Completed`]) or, when `stop` says so
    /// after a record, at that step boundary ([`RunEnd::Interrupted`]). Returns the last record
    /// and how the walk ended: the error of a step (the record before it is the last) or of `take`
    /// ends it too, and so does a record with a NaN or an infinity, which is never handed over
    /// ([`StepRecord::check_finite`]: the stepper checks every state it reaches but the stresses,
    /// which the record adds; that record, of the state `sim` is in, is then the last).
    pub fn walk(
        &self,
        sim: &mut Simulation,
        mut take: impl FnMut(&mut Simulation, &StepRecord) -> Result<(), Error>,
        mut stop: impl FnMut() -> bool,
    ) -> (StepRecord, Result<RunEnd, Error>) {
        let mut record = sim.record(sim.last_newton_iterations());
        loop {
            if let Err(e) = record.check_finite().and_then(|()| take(sim, &record)) {
                return (record, Err(e));
            }
            if self.done(sim) {
                return (record, Ok(RunEnd::Completed));
            }
            if stop() {
                return (record, Ok(RunEnd::Interrupted));
            }
            // the stepper advances; the record (with the nodal stresses) is the walk's observation
            match self.take(sim) {
                Ok(its) => record = sim.record(its),
                Err(e) => return (record, Err(e)),
            }
        }
    }
}
