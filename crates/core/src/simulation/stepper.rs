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
//! * **No state with a NaN or an infinity.** A step whose state has a quantity of its record
//!   (the stresses aside) that is NaN or infinite fails so too, with [`Error::NonFinite`] naming
//!   it ([`StepRecord::check_finite`]); so does the set-up of an initial state with one. The
//!   outputs on request of a state that a step or the set-up reached are finite.
//! * **Inputs held between steps**: [`Simulation::set_torque`] replaces the `[torque]` profile by a
//!   value held until it is set again (a zero-order hold: the step uses it from its start to its end).
//! * **Outputs on request**: [`Simulation::time`], [`Simulation::theta`],
//!   [`Simulation::angular_rates`], [`Simulation::energies`], [`Simulation::hinge_reaction`],
//!   [`Simulation::von_mises_max`], [`Simulation::last_newton_iterations`]; the fields
//!   [`Simulation::displacement`], [`Simulation::velocity`], [`Simulation::acceleration_field`],
//!   [`Simulation::nodal_stress`]. A step computes none of the stresses; they cost a pass over every
//!   element node and are made only when asked for.

use super::{Clock, Simulation, StepRecord};
use crate::constraint::Hinge;
use crate::error::Error;
use crate::post::NodalStress;

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
    /// error ([`Error::TimeStep`], or [`Error::NonFinite`] for a state with a NaN or an infinity)
    /// is returned; `dt` out of range is [`Error::Input`].
    pub fn step(&mut self, dt: f64) -> Result<usize, Error> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::Input(format!(
                "step(dt = {dt} s) at t = {} s: allowed dt > 0 and finite",
                self.now.state.t
            )));
        }
        let clock = self.clock.after(dt);
        self.output_step(dt, clock)
    }

    /// Advances the state by one step to exactly `t_end` \[s\] (after the current time), for a last
    /// step that lands on an end time; otherwise as [`Simulation::step`].
    pub fn step_to(&mut self, t_end: f64) -> Result<usize, Error> {
        let t0 = self.now.state.t;
        let dt = t_end - t0;
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::Input(format!(
                "step_to(t_end = {t_end} s) from t = {t0} s: the end must lie after the current time"
            )));
        }
        self.output_step(dt, Clock::at(t_end))
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
        self.now.held_torque = Some(value);
        self.now.forget_measures();
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
        self.now.held_torque
    }

    /// Time of the current state \[s\].
    pub fn time(&self) -> f64 {
        self.now.state.t
    }

    /// Proxy angle of the current state, unwrapped (continuous past ±π) \[rad\].
    pub fn theta(&self) -> f64 {
        self.now.theta
    }

    /// Newton iterations (linear solves) of the last step: its sub-steps, and the attempts that
    /// failed and were halved (0 before the first step).
    pub fn last_newton_iterations(&self) -> usize {
        self.last_iterations
    }

    /// Kinetic, strain and gravitational energy of the current state and the torque's work \[J\].
    pub fn energies(&mut self) -> Energies {
        let kinetic = self.kinematics().kinetic;
        self.body.prepare_energies(&self.model, &self.now);
        self.energies_with(kinetic)
    }

    /// The energies of the current state with its kinetic energy \[J\] already computed: the one
    /// definition of the total energy, for [`Simulation::energies`] and the records. The
    /// potential energies are computed once for a state (the strain energy's two ways, from the
    /// start data or the fields, give the same bits).
    pub(super) fn energies_with(&mut self, kinetic: f64) -> Energies {
        let [strain, gravity, contact] = match self.now.energies {
            Some(energies) => energies,
            None => *self.now.energies.insert(self.body.energies(&self.model, &self.now)),
        };
        Energies {
            kinetic,
            strain,
            gravity,
            contact,
            total: kinetic + strain + gravity + contact,
            torque_work: self.now.torque_work,
        }
    }

    /// The gap of the current state \[m\], positive while apart: with a wall, the smallest gap of
    /// the head's arc to its face (negative: the largest penetration; the `gap_m` column of
    /// `results.csv`); without one, the smallest signed distance of the arc's nodes to the plane
    /// `x = wall.x` (`+∞` for a mesh without the arc).
    pub fn gap(&self) -> f64 {
        self.body.gap(&self.model, &self.now)
    }

    /// The normal force of the wall on the head in the current state \[N\] (the `contact_force_N`
    /// column of `results.csv`, a negative zero as 0); 0 without a wall. The one reading of the
    /// contact force for the FMU's and the Python package's outputs.
    pub fn contact_force(&self) -> f64 {
        self.body.contact_force(&self.model, &self.now)
    }

    /// Force of the hinge on the body \[N\].
    pub fn hinge_reaction(&self) -> [f64; 2] {
        Hinge::reaction(self.now.lambda)
    }

    /// Nodal displacement, interleaved `[u_x, u_y]` per node \[m\].
    pub fn displacement(&self) -> &[f64] {
        self.body.fields(&self.now)[0]
    }

    /// Nodal velocity, interleaved \[m/s\].
    pub fn velocity(&self) -> &[f64] {
        self.body.fields(&self.now)[1]
    }

    /// Nodal Cauchy and von Mises stresses of the current state (computed on this call).
    pub fn nodal_stress(&mut self) -> NodalStress {
        self.stress_evaluations += 1;
        self.body.nodal_stress(&self.model, &self.now)
    }

    /// The largest nodal von Mises stress of the current state \[Pa\] (computed on this call).
    pub fn von_mises_max(&mut self) -> f64 {
        self.stress_evaluations += 1;
        self.body.von_mises_max(&self.model, &self.now)
    }

    /// How often nodal stresses were computed so far (by [`Simulation::nodal_stress`],
    /// [`Simulation::von_mises_max`], records and frames; never by a step).
    pub fn stress_evaluations(&self) -> usize {
        self.stress_evaluations
    }

    /// Nonzeros of the full body's factor (0 for the reduced body).
    pub fn factor_nnz(&self) -> usize {
        self.body.factor_nnz()
    }

    /// The torque's work since the start \[J\].
    pub fn torque_work(&self) -> f64 {
        self.now.torque_work
    }

    /// The reduced body's largest error estimate so far and when it was reached `(η, t)`
    /// ([`crate::reduced::validity`]); `None` for the full body.
    pub fn error_estimate(&self) -> Option<(f64, f64)> {
        self.body.error_estimate()
    }

    /// A warning the run has raised since the last call (the reduced body's, once, when it does
    /// not apply), for the driver to show.
    pub fn take_warning(&mut self) -> Option<String> {
        self.body.take_warning()
    }

    /// The reduced body's coordinates and momenta, `None` for the full body.
    pub fn reduced_state(&self) -> Option<&crate::reduced::ReducedState> {
        self.body.reduced_state()
    }
}
