//! The parameters of an instance: values set by value reference, the configuration they stand for
//! (configuration overrides by name, the torque input declared), their own checks, the warnings
//! for parameters set where they have no effect, and the simulation built from them when first
//! needed.

use pendulum_fem_core::config::{GivenKeys, Use};
use pendulum_fem_core::simulation::Built;
use pendulum_fem_core::{Config, Error, Simulation};

use super::{Instance, Phase, Status, SET_PHASES};
use crate::variables::{Causality, Kind, Role, VARIABLES};

impl Instance {
    /// The current value of the table entry with this role.
    pub(super) fn value_of(&self, role: Role) -> f64 {
        let i = VARIABLES
            .iter()
            .position(|v| v.role == role)
            .expect("role in the table");
        self.values[i]
    }

    /// The configuration of the current parameter values: the CLI's defaults, each parameter with a
    /// configuration key set by name, `initial.angle_deg` from `theta_start`, and the torque input
    /// declared (`[torque] profile = "constant", amplitude = 0`).
    pub fn config(&self) -> Result<Config, Error> {
        let sets: Vec<String> = VARIABLES
            .iter()
            .zip(&self.values)
            .filter_map(|(v, &value)| assignment(v.role, v.kind, value))
            .collect();
        Config::load(None, &sets).map(|c| c.with_torque_input())
    }

    /// The warnings for the parameters set away from their start values that have no effect in
    /// `config` (the configuration they stand for, [`Config::ineffective_keys`] of a stepped
    /// simulation): each names the parameter, and the parameters that set the keys it names. A
    /// parameter at its start value counts as not set: a master may set every start value.
    fn ineffective(&self, config: &Config) -> Vec<String> {
        let changed: Vec<String> = VARIABLES
            .iter()
            .zip(&self.values)
            .filter(|(v, &value)| v.start.is_some_and(|s| s.to_bits() != value.to_bits()))
            .filter_map(|(v, &value)| assignment(v.role, v.kind, value))
            .collect();
        let given = GivenKeys::of_overrides(&changed);
        config
            .ineffective_keys(&given, Use::Stepper)
            .iter()
            .map(|w| {
                let text = w.to_string();
                let name = |key: &str| {
                    VARIABLES
                        .iter()
                        .find(|v| config_key(v.role) == Some(key))
                        .map(|v| v.name)
                };
                let others: Vec<String> = VARIABLES
                    .iter()
                    .filter_map(|v| config_key(v.role).map(|key| (key, v.name)))
                    .filter(|&(key, _)| key != w.key && w.reason.contains(key))
                    .map(|(key, name)| format!("{key} is the parameter {name}"))
                    .collect();
                let others = match others.is_empty() {
                    true => String::new(),
                    false => format!(" (in this FMU {})", others.join(", ")),
                };
                format!("parameter {}: {text}{others}", name(w.key).unwrap_or(w.key))
            })
            .collect()
    }

    /// Checks the parameters that are not configuration keys.
    fn check_own_parameters(&self) -> Result<(), String> {
        let h = self.value_of(Role::MaxInternalStep);
        if !(h > 0.0 && h.is_finite()) {
            return Err(format!("max_internal_step = {h}: allowed a finite value > 0 s"));
        }
        let w = self.value_of(Role::WallKind);
        if !(0.0..=2.0).contains(&w) {
            return Err(format!(
                "wall_kind = {w}: allowed 0 (none), 1 (rigid) or 2 (deformable)"
            ));
        }
        let k = self.value_of(Role::ModelKind);
        if !(0.0..=1.0).contains(&k) {
            return Err(format!("model_kind = {k}: allowed 0 (full) or 1 (reduced)"));
        }
        let t = self.value_of(Role::ThetaStart);
        if !(-2.0 * std::f64::consts::PI..=2.0 * std::f64::consts::PI).contains(&t) {
            return Err(format!("theta_start = {t}: allowed -2 pi to 2 pi rad"));
        }
        Ok(())
    }

    /// Builds the simulation if there is none or a parameter changed ([`Simulation::build`], the
    /// set-up every front end shares); errors are logged, and so are the mesh-size warning of a
    /// `mesh_max_size` that bounds no element and the warnings for parameters without effect.
    pub(super) fn ensure_sim(&mut self) -> Result<(), Status> {
        if self.sim.is_some() && !self.stale {
            return Ok(());
        }
        if let Err(e) = self.check_own_parameters() {
            return Err(self.error(&format!("invalid parameter: {e}")));
        }
        let built = self.config().and_then(|cfg| {
            let Built {
                mut simulation,
                mesh_warning,
                ..
            } = Simulation::build(&cfg)?;
            let tau = self.value_of(Role::Tau);
            if tau != 0.0 {
                simulation.set_torque(tau)?;
            }
            Ok((simulation, mesh_warning))
        });
        match built {
            Ok((sim, mesh_warning)) => {
                self.info(&format!(
                    "model built: {} triangles, {} nodes, theta = {} rad",
                    sim.model.mesh.triangles.len(),
                    sim.model.mesh.num_nodes(),
                    sim.theta()
                ));
                if let Some(w) = mesh_warning {
                    self.warning(&w);
                }
                for w in self.ineffective(&sim.model.config) {
                    self.warning(&w);
                }
                self.sim = Some(sim);
                self.log_warning();
                self.invalidate();
                self.stale = false;
                Ok(())
            }
            Err(e) => {
                self.sim = None;
                Err(self.error(&format!("invalid parameters, the model cannot be built: {e}")))
            }
        }
    }

    /// Sets values by value reference (`fmi2SetReal`, `…Integer`, `…Boolean`): parameters in the
    /// instantiated state and initialization mode, the input `tau` until `fmi2Terminate`. The
    /// computed outputs are kept when no value changes: a master that sets the same input again
    /// before it reads (fmpy every step, an iterating master every iteration) does not pay for
    /// them again (the total energy is a pass over the mesh).
    pub fn set(&mut self, kind: Kind, vrs: &[u32], values: &[f64]) -> Status {
        let function = &self.typed_call("Set", kind);
        if let Err(status) = self.check_phase(function, SET_PHASES) {
            return status;
        }
        for (&vr, &value) in vrs.iter().zip(values) {
            let Some((i, v)) = crate::variables::lookup(vr, kind) else {
                return self.error(&format!("{function}: no {kind:?} variable with value reference {vr}"));
            };
            match v.causality {
                Causality::Output => return self.error(&format!("{function}: {} is an output", v.name)),
                Causality::Parameter if !matches!(self.phase, Phase::Instantiated | Phase::Initialization) => {
                    return self.error(&format!(
                        "{function}: {} is a fixed parameter, not settable in the {} state; set it before \
                         {}ExitInitializationMode",
                        v.name,
                        self.phase.name(),
                        self.api.prefix()
                    ));
                }
                Causality::Parameter => {
                    if self.values[i].to_bits() != value.to_bits() {
                        self.stale = true;
                        self.invalidate();
                    }
                    self.values[i] = value;
                }
                Causality::Input => {
                    if !value.is_finite() {
                        return self.error(&format!("{function}: {} = {value} is not finite", v.name));
                    }
                    let changed = self.values[i].to_bits() != value.to_bits();
                    // a refused input leaves the held one in place
                    if let (true, Some(sim), false) = (changed, self.sim.as_mut(), self.stale) {
                        if let Err(e) = sim.set_torque(value) {
                            let t = self.time();
                            return self.error(&format!("{function}: tau = {value} N.m at t = {t} s: {e}"));
                        }
                    }
                    if changed {
                        self.input_changed();
                        self.invalidate();
                    }
                    self.values[i] = value;
                }
            }
        }
        Status::Ok
    }
}

/// The configuration key a parameter of this role sets.
fn config_key(role: Role) -> Option<&'static str> {
    match role {
        Role::Config(key) => Some(key),
        Role::ThetaStart => Some("initial.angle_deg"),
        Role::MaxCutbacks => Some("solver.max_cutbacks"),
        Role::WallKind => Some("wall.kind"),
        Role::ModelKind => Some("model.kind"),
        _ => None,
    }
}

/// The `key=value` override a parameter of this role and kind with `value` stands for (`None`:
/// no configuration key).
fn assignment(role: Role, kind: Kind, value: f64) -> Option<String> {
    Some(match role {
        Role::Config(key) => match kind {
            Kind::Real => format!("{key}={value:?}"),
            _ => format!("{key}={}", value as i64),
        },
        Role::ThetaStart => format!("initial.angle_deg={:?}", value.to_degrees()),
        Role::MaxCutbacks => match value as i64 {
            -1 => "solver.max_cutbacks=\"auto\"".to_string(),
            count => format!("solver.max_cutbacks={count}"),
        },
        Role::WallKind => match value as i64 {
            0 => "wall.kind=\"none\"".to_string(),
            1 => "wall.kind=\"rigid\"".to_string(),
            2 => "wall.kind=\"deformable\"".to_string(),
            other => format!("wall.kind={other}"),
        },
        Role::ModelKind => match value as i64 {
            0 => "model.kind=\"full\"".to_string(),
            1 => "model.kind=\"reduced\"".to_string(),
            other => format!("model.kind={other}"),
        },
        _ => return None,
    })
}
