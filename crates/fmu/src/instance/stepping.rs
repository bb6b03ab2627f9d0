//! Stepping an instance and reading its values: `fmi2DoStep` split into internal steps, and the
//! outputs of the current state, computed on the first request after a change and kept until the next.

use pendulum_fem_core::simulation::split;

use super::{Instance, Phase, Status, GET_PHASES, OUTPUTS, TIME_TOLERANCE};
use crate::contact::contact_outputs;
use crate::variables::{Kind, Output, Role};

impl Instance {
    /// Reads values by value reference (`fmi2GetReal`, `…Integer`, `…Boolean`) into `out`: from
    /// initialization mode on (FMI 2.0 does not allow it in the instantiated state).
    pub fn get(&mut self, kind: Kind, vrs: &[u32], out: &mut [f64]) -> Status {
        let function = &self.typed_call("Get", kind);
        if let Err(status) = self.check_phase(function, GET_PHASES) {
            return status;
        }
        for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
            if (self.api, kind, vr) == (super::Api::Fmi3, Kind::Real, crate::variables::TIME_VR_FMI3) {
                *slot = self.time();
                continue;
            }
            let Some((i, v)) = crate::variables::lookup(vr, kind) else {
                return self.error(&format!("{function}: no {kind:?} variable with value reference {vr}"));
            };
            *slot = match v.role {
                Role::Output(which) => match self.output(which) {
                    Ok(value) => value,
                    Err(status) => return status,
                },
                _ => self.values[i],
            };
        }
        Status::Ok
    }

    /// One output of the current state, computed on the first request after a change of the state
    /// (a step, a torque input, a restored state) and kept until the next: a master that reads
    /// every output with three calls (Real, Integer, Boolean) pays for each once.
    fn output(&mut self, which: Output) -> Result<f64, Status> {
        // FMI 3.0: the discrete outputs change at events (module `events`)
        match (which, self.discrete_outputs()) {
            (Output::ContactCount, Some((count, _))) => return Ok(f64::from(count)),
            (Output::Impact, Some((_, impact))) => return Ok(f64::from(u8::from(impact))),
            _ => {}
        }
        if let Some(value) = self.cache[which as usize] {
            return Ok(value);
        }
        self.ensure_sim()?;
        let impact = self.impact;
        let sim = self.sim.as_mut().expect("built above");
        let cache = &mut self.cache;
        match which {
            Output::Theta => cache[Output::Theta as usize] = Some(sim.theta()),
            Output::Omega | Output::Alpha => {
                let (omega, alpha) = sim.angular_rates();
                cache[Output::Omega as usize] = Some(omega);
                cache[Output::Alpha as usize] = Some(alpha);
            }
            Output::TotalEnergy => cache[Output::TotalEnergy as usize] = Some(sim.energies().total),
            Output::Gap | Output::ContactForce | Output::ContactCount | Output::Impact => {
                let c = contact_outputs(sim, impact);
                cache[Output::Gap as usize] = Some(c.gap);
                cache[Output::ContactForce as usize] = Some(c.force);
                cache[Output::ContactCount as usize] = Some(f64::from(c.count));
                cache[Output::Impact as usize] = Some(f64::from(u8::from(c.impact)));
            }
        }
        Ok(self.cache[which as usize].expect("computed above"))
    }

    /// Forgets the computed outputs (the state or an input changed).
    pub(super) fn invalidate(&mut self) {
        self.cache = [None; OUTPUTS];
    }

    /// `fmi2DoStep(t, h)` (see the module doc).
    pub fn do_step(&mut self, t: f64, h: f64) -> Status {
        match self.check_step("fmi2DoStep", t, h) {
            Err(status) => return status,
            // an output refresh: outputs are computed on request from the current state
            Ok(false) => return Status::Ok,
            Ok(true) => {}
        }
        let impacts_before = self.sim.as_ref().map_or(0, |sim| sim.impacts());
        if let Err(status) = self.internal_steps("fmi2DoStep", h, None) {
            return status;
        }
        self.impact = self.sim.as_ref().map_or(0, |sim| sim.impacts()) > impacts_before;
        Status::Ok
    }

    /// The checks of a `doStep(t, h)` request (`function` names it): step mode, `h` finite and
    /// `>= 0`, `t` within [`TIME_TOLERANCE`] of the FMU's time. `Ok(false)` for `h = 0`.
    pub(super) fn check_step(&self, function: &str, t: f64, h: f64) -> Result<bool, Status> {
        self.check_phase(function, &[Phase::StepMode])?;
        let now = self.time();
        if !(h >= 0.0 && h.is_finite()) {
            return Err(self.error(&format!(
                "{function} at t = {now} s: communicationStepSize = {h} s; allowed a finite value >= 0 s"
            )));
        }
        // NaN is never within
        let within = (t - now).abs() <= TIME_TOLERANCE * now.abs().max(1.0);
        if !within {
            return Err(self.error(&format!(
                "{function}: currentCommunicationPoint = {t} s is not the FMU's time {now} s (tolerance {TIME_TOLERANCE} relative)"
            )));
        }
        Ok(h != 0.0)
    }

    /// Advances by `h > 0` in the internal steps of [`split::internal_steps`]; a failure leaves the
    /// state as before the call. With `watch` (FMI 3.0's early return: the impacts announced so
    /// far and the communication point) it stops at the start of the first impact not yet
    /// announced ([`Instance::return_early`]).
    pub(super) fn internal_steps(
        &mut self,
        function: &str,
        h: f64,
        watch: Option<(usize, f64)>,
    ) -> Result<Option<super::events::Early>, Status> {
        let now = self.time();
        let max_step = self.value_of(Role::MaxInternalStep);
        let (n, sub) = match split::internal_steps(h, max_step, self.last_internal_step) {
            Ok(split) => split,
            Err(e) => return Err(self.error(&format!("{function} from t = {now} s by h = {h} s refused: {e}"))),
        };
        let sim = self.sim.as_mut().expect("built at exitInitializationMode");
        let before = (n > 1 || watch.is_some()).then(|| sim.snapshot());
        // the start of every internal step, to go back to an impact's start
        let mut starts = Vec::new();
        for k in 0..n {
            let sim = self.sim.as_mut().expect("built");
            if watch.is_some() {
                starts.push((sim.time(), sim.snapshot()));
            }
            let stepped = sim.step(sub);
            self.log_warning();
            let sim = self.sim.as_mut().expect("built");
            let early = match (stepped, watch) {
                (Err(e), _) => {
                    let failed_at = self.start_time + sim.time();
                    if let Some(before) = &before {
                        sim.restore(before).expect("a snapshot of this model restores");
                    }
                    return Err(self.error(&format!(
                        "{function} from t = {now} s by h = {h} s failed in internal step {} of {n} at t = {failed_at} s \
                         (the state is as before the call): {e}",
                        k + 1
                    )));
                }
                (Ok(_), Some(watch)) => self.return_early(function, watch, &starts),
                (Ok(_), None) => Ok(None),
            };
            match early {
                Ok(None) => {}
                Ok(Some(early)) => {
                    self.last_internal_step = Some(sub);
                    self.invalidate();
                    return Ok(Some(early));
                }
                Err(status) => {
                    let sim = self.sim.as_mut().expect("built");
                    sim.restore(before.as_ref().expect("taken when watching"))
                        .expect("a snapshot of this model restores");
                    return Err(status);
                }
            }
        }
        self.last_internal_step = Some(sub);
        self.invalidate();
        Ok(None)
    }
}
