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
        let function = match kind {
            Kind::Real => "fmi2GetReal",
            Kind::Integer => "fmi2GetInteger",
            Kind::Boolean => "fmi2GetBoolean",
        };
        if let Err(status) = self.check_phase(function, GET_PHASES) {
            return status;
        }
        for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
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
        if let Err(status) = self.check_phase("fmi2DoStep", &[Phase::StepMode]) {
            return status;
        }
        let now = self.time();
        if !(h >= 0.0 && h.is_finite()) {
            return self.error(&format!(
                "fmi2DoStep at t = {now} s: communicationStepSize = {h} s; allowed a finite value >= 0 s"
            ));
        }
        // NaN is never within
        let within = (t - now).abs() <= TIME_TOLERANCE * now.abs().max(1.0);
        if !within {
            return self.error(&format!(
                "fmi2DoStep: currentCommunicationPoint = {t} s is not the FMU's time {now} s (tolerance {TIME_TOLERANCE} relative)"
            ));
        }
        if h == 0.0 {
            // an output refresh: outputs are computed on request from the current state
            return Status::Ok;
        }
        let max_step = self.value_of(Role::MaxInternalStep);
        let (n, sub) = match split::internal_steps(h, max_step, self.last_internal_step) {
            Ok(split) => split,
            Err(e) => return self.error(&format!("fmi2DoStep from t = {now} s by h = {h} s refused: {e}")),
        };
        let sim = self.sim.as_mut().expect("built at exitInitializationMode");
        let before = (n > 1).then(|| sim.snapshot());
        let impacts_before = sim.impacts();
        for k in 0..n {
            if let Err(e) = sim.step(sub) {
                let failed_at = self.start_time + sim.time();
                if let Some(before) = &before {
                    sim.restore(before).expect("a snapshot of this model restores");
                }
                return self.error(&format!(
                    "fmi2DoStep from t = {now} s by h = {h} s failed in internal step {} of {n} at t = {failed_at} s \
                     (the state is as before the call): {e}",
                    k + 1
                ));
            }
        }
        self.last_internal_step = Some(sub);
        self.impact = sim.impacts() > impacts_before;
        self.invalidate();
        Status::Ok
    }
}
