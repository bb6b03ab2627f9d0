//! One output step of a [`Simulation`] in sub-steps and cut-backs: split into equal sub-steps by
//! the predicted rotation, each halved on failure as `solver.max_cutbacks` allows
//! ([`crate::config::Cutbacks`]).

use super::Simulation;
use crate::config::Scheme;
use crate::error::NewtonError;
use crate::terms::StepContext;
use crate::Error;

/// The largest predicted turn of one energy-momentum (sub)step \[rad\]: a quarter turn. A light
/// body spun up by a torque (1800 rad/s at dt = 13 ms, 24 rad per step) is sub-stepped instead of
/// cut back from failure to failure.
const EM_MAX_TURN: f64 = std::f64::consts::FRAC_PI_2;

impl Simulation {
    /// Advances by `dt`, halving on failure; returns the Newton iterations used.
    pub(super) fn advance_by(&mut self, dt: f64) -> Result<usize, (NewtonError, f64)> {
        if self.model.reduced.is_some() {
            return self.advance_reduced(dt);
        }
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

    /// One output step of length `dt`: sub-steps (the Newmark schemes beyond
    /// `time.max_rotation_deg`, see [`Simulation::advance`]; the energy-momentum scheme beyond a
    /// quarter turn, [`EM_MAX_TURN`]), cut-backs, the step counter; returns the Newton iterations.
    pub(super) fn advance_over(&mut self, dt: f64) -> Result<usize, Error> {
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
}
