//! Keys without effect: a key the user gave ([`GivenKeys`]) that the configuration it sits in does
//! not use, with what would make it act ([`Config::ineffective_keys`]). The one rule for every
//! front end: the CLI prints each as `warning: …` (and keeps it in the run's summary and
//! `status.json`), the Python package raises it as a `UserWarning`, the FMU logs it with the
//! warning status. Only given keys are named: a key that holds its default warns of nothing.
//!
//! What does not act, and when (the reasons below say what would make each act):
//!
//! | keys | no effect when |
//! |---|---|
//! | `torque.*` but `profile` | `torque.profile = "none"` (`follower` acts in a stepper: its `tau` input turns with it) |
//! | `torque.amplitude` | `profile = "table"` (the table holds the torque) |
//! | `torque.start` | `profile` `"constant"` or `"table"` |
//! | `torque.duration` | `profile` other than `"ramp"` |
//! | `torque.frequency`, `torque.phase` | `profile` other than `"sine"` |
//! | `torque.file` | `profile` other than `"table"` |
//! | `wall.*` but `kind`, `contact.*`, `model.contact_modes` | `wall.kind = "none"` (`wall.x` acts in a stepper: its gap is measured to the plane `x = wall.x`) |
//! | the block's material and mesh (`wall.youngs_modulus`, `poisson_ratio`, `density`, `thickness`, `mesh_size`, `face_size`) | `wall.kind = "rigid"` |
//! | `wall.width`, `height`, `center_y` | `wall.kind = "rigid"`, unless a run draws the block in its ParaView files |
//! | `contact.substeps` | `contact.method = "penalty"` (no impact is resolved in sub-steps) |
//! | `model.modes`, `model.contact_modes` | `model.kind = "full"` |
//! | `time.dissipation`, `solver.tolerance`, `solver.energy_tolerance`, `solver.max_iterations` | `model.kind = "reduced"` (its steps have a rule and a Newton of their own) |
//! | `solver.energy_tolerance` | `time.scheme` other than `"energy-momentum"` |
//! | `time.hht_alpha` | `time.scheme` other than `"hht"` |
//! | `time.max_rotation_deg` | `time.scheme = "energy-momentum"` |
//! | the generated mesh's keys (`mesh.*` but `file`), `geometry.rod_half_width`, `hole_radius` | `mesh.file` is set |
//! | `geometry.head_radius`, `head_center_distance` | `mesh.file` is set and there is no wall (with one, they size the impact sub-steps) |
//! | `output.paraview_every` | `output.paraview = false` |
//! | `output.max_frames`, `output.magnification` | `output.animation` and `output.viewer` false |
//! | `output.every` | as those, and no ParaView frames it thins |
//! | `output.*`, `time.end` | in a stepper, which writes no files and runs as far as it is stepped |

use std::fmt;

use super::given::{GivenKeys, Place};
use super::{Config, ContactMethod, ModelKind, Scheme, TorqueProfile, WallKind};

/// What runs a configuration: whether some keys act depends on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Use {
    /// A run that writes its folder: `pendulum-fem run` (and the CLI's other commands), a case of
    /// a sweep or of a study.
    Run,
    /// A simulation that its caller steps and reads: the FMU, the Python package's `Simulation`.
    /// It writes no files (`[output]`) and runs as far as it is stepped (`time.end`); its gap is
    /// the distance to the plane `x = wall.x` without a wall too, and a `tau` input declared
    /// after the start turns with the body as `torque.follower` says.
    Stepper,
}

/// A given key that has no effect where it sits: `torque.amplitude = 2 has no effect: no torque
/// profile is set (set torque.profile to one of …)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Ineffective {
    /// The key, `section.name`.
    pub key: &'static str,
    /// Its value as written.
    pub value: String,
    /// Why it has no effect, and what would make it act.
    pub reason: String,
    /// Where it was written.
    pub place: Place,
}

impl fmt::Display for Ineffective {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {} has no effect: {}", self.key, self.value, self.reason)
    }
}

/// The profiles that use a torque key, as a remedy: `set torque.profile to "ramp"` or `… to one of
/// "step", "ramp" or "sine"`.
fn set_profile(profiles: &[TorqueProfile]) -> String {
    let names: Vec<String> = profiles.iter().map(|p| format!("\"{}\"", p.name())).collect();
    match names.as_slice() {
        [one] => format!("set torque.profile to {one}"),
        [most @ .., last] => format!("set torque.profile to one of {} or {last}", most.join(", ")),
        [] => String::new(),
    }
}

impl Config {
    /// The keys of `given` that have no effect in this configuration run as `used`, in the order
    /// they were written, each with why and what would make it act (see the module doc).
    pub fn ineffective_keys(&self, given: &GivenKeys, used: Use) -> Vec<Ineffective> {
        let mut found: Vec<Ineffective> = self
            .unused_keys(used)
            .into_iter()
            .flat_map(|(keys, reason)| {
                keys.iter()
                    .filter_map(|&key| {
                        given.get(key).map(|g| Ineffective {
                            key,
                            value: g.value.clone(),
                            reason: reason.clone(),
                            place: g.place,
                        })
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        found.sort_by_key(|w| w.place);
        found
    }

    /// The keys this configuration does not use when run as `used`, in groups with the reason.
    fn unused_keys(&self, used: Use) -> Vec<(Vec<&'static str>, String)> {
        let mut unused: Vec<(Vec<&'static str>, String)> = Vec::new();
        let mut none = |keys: &[&'static str], reason: String| unused.push((keys.to_vec(), reason));
        let stepper = used == Use::Stepper;
        let reduced = self.model.kind == ModelKind::Reduced;
        let wall = self.wall.is_present();

        // [torque]
        use TorqueProfile as P;
        let profile = self.torque.profile;
        if profile == P::None {
            let mut keys = vec![
                "torque.amplitude",
                "torque.start",
                "torque.duration",
                "torque.frequency",
                "torque.phase",
                "torque.file",
            ];
            if !stepper {
                keys.push("torque.follower");
            }
            none(
                &keys,
                format!(
                    "no torque profile is set ({})",
                    set_profile(&[P::Constant, P::Step, P::Ramp, P::Sine, P::Table])
                ),
            );
        } else {
            let by = |uses: &[P]| {
                format!(
                    "torque.profile = \"{}\" does not use it ({})",
                    profile.name(),
                    set_profile(uses)
                )
            };
            for (key, uses) in [
                ("torque.amplitude", &[P::Constant, P::Step, P::Ramp, P::Sine][..]),
                ("torque.start", &[P::Step, P::Ramp, P::Sine]),
                ("torque.duration", &[P::Ramp]),
                ("torque.frequency", &[P::Sine]),
                ("torque.phase", &[P::Sine]),
                ("torque.file", &[P::Table]),
            ] {
                if !uses.contains(&profile) {
                    none(&[key], by(uses));
                }
            }
        }

        // [wall], [contact], the reduced body's contact modes
        let no_wall = || "there is no wall (set wall.kind to \"rigid\" or \"deformable\")".to_string();
        let block = [
            "wall.youngs_modulus",
            "wall.poisson_ratio",
            "wall.density",
            "wall.thickness",
            "wall.mesh_size",
            "wall.face_size",
        ];
        let extent = ["wall.width", "wall.height", "wall.center_y"];
        match self.wall.kind {
            WallKind::None => {
                if !stepper {
                    none(&["wall.x"], no_wall());
                }
                none(&extent, no_wall());
                none(&block, no_wall());
                none(
                    &[
                        "contact.method",
                        "contact.stiffness",
                        "contact.points_per_edge",
                        "contact.substeps",
                    ],
                    no_wall(),
                );
                if reduced {
                    none(&["model.contact_modes"], no_wall());
                }
            }
            WallKind::Rigid => {
                let rigid = "the rigid wall (wall.kind = \"rigid\") is the half-plane x <= wall.x, without a block";
                none(&block, format!("{rigid} (set wall.kind to \"deformable\")"));
                let drawn = match used {
                    Use::Stepper => Some("which a stepped simulation does not write"),
                    Use::Run if !self.output.paraview => Some("and output.paraview = false"),
                    Use::Run => None,
                };
                if let Some(drawn) = drawn {
                    none(
                        &extent,
                        format!("{rigid}; only the ParaView files draw one, {drawn} (set wall.kind to \"deformable\")"),
                    );
                }
            }
            WallKind::Deformable => {}
        }
        if wall && self.contact.method == ContactMethod::Penalty {
            none(
                &["contact.substeps"],
                "contact.method = \"penalty\" resolves no impact in sub-steps (set contact.method to \
                 \"energy-consistent\")"
                    .into(),
            );
        }

        // [model], [time], [solver]
        let scheme = self.time.scheme;
        if !reduced {
            none(
                &["model.modes", "model.contact_modes"],
                "the full body (model.kind = \"full\") has no modes (set model.kind to \"reduced\")".into(),
            );
        }
        if reduced {
            none(
                &[
                    "time.dissipation",
                    "solver.tolerance",
                    "solver.energy_tolerance",
                    "solver.max_iterations",
                ],
                "the reduced body (model.kind = \"reduced\") takes its steps by a rule and a Newton of its own, \
                 without numerical dissipation (set model.kind to \"full\")"
                    .into(),
            );
        } else if scheme != Scheme::EnergyMomentum {
            none(
                &["solver.energy_tolerance"],
                format!(
                    "it bounds the energy error of time.scheme = \"energy-momentum\", and this one is \"{}\" (set \
                     time.scheme to \"energy-momentum\")",
                    scheme.name()
                ),
            );
        }
        if scheme != Scheme::Hht {
            none(
                &["time.hht_alpha"],
                format!(
                    "time.scheme = \"{}\" does not use it (set time.scheme to \"hht\")",
                    scheme.name()
                ),
            );
        }
        if scheme == Scheme::EnergyMomentum {
            none(
                &["time.max_rotation_deg"],
                "time.scheme = \"energy-momentum\" splits no step by its rotation (set time.scheme to \
                 \"trapezoidal\" or \"hht\")"
                    .into(),
            );
        }

        // [mesh], [geometry]: a mesh read from a file
        if self.mesh.file.is_some() {
            let remedy = "remove mesh.file to mesh the pendulum of [geometry]";
            none(
                &[
                    "mesh.max_size",
                    "mesh.order",
                    "mesh.rod_size",
                    "mesh.head_size",
                    "mesh.hinge_edge_size",
                    "mesh.hinge_corner_size",
                    "mesh.circle_edge_size",
                    "mesh.grading",
                    "mesh.refine",
                    "geometry.rod_half_width",
                    "geometry.hole_radius",
                ],
                format!("the mesh is read from mesh.file ({remedy})"),
            );
            if !wall {
                none(
                    &["geometry.head_radius", "geometry.head_center_distance"],
                    format!(
                        "the mesh is read from mesh.file, and besides the mesher only a wall's impact sub-steps \
                         read it ({remedy})"
                    ),
                );
            }
        }

        // [output], time.end
        if stepper {
            none(
                &["time.end"],
                "a simulation stepped by its caller runs as far as it is stepped (time.end ends the runs of \
                 pendulum-fem run and its sweeps)"
                    .into(),
            );
            none(
                &[
                    "output.dir",
                    "output.every",
                    "output.paraview_every",
                    "output.magnification",
                    "output.plots",
                    "output.animation",
                    "output.paraview",
                    "output.viewer",
                    "output.max_frames",
                    "output.energy_watchdog",
                ],
                "a simulation stepped by its caller writes no files (the [output] keys act in pendulum-fem run \
                 and its sweeps)"
                    .into(),
            );
        } else {
            let o = &self.output;
            if !o.paraview {
                none(
                    &["output.paraview_every"],
                    "output.paraview = false writes no ParaView frames (set output.paraview to true)".into(),
                );
            }
            if !o.animation && !o.viewer {
                none(
                    &["output.max_frames", "output.magnification"],
                    "output.animation and output.viewer are false, and they alone draw these frames (set either to \
                     true)"
                        .into(),
                );
                let paraview = match (o.paraview, o.paraview_every) {
                    (false, _) => Some("output.paraview is false"),
                    (true, Some(_)) => Some("output.paraview_every thins the ParaView frames"),
                    (true, None) => None,
                };
                if let Some(paraview) = paraview {
                    none(
                        &["output.every"],
                        format!(
                            "output.animation and output.viewer are false, and {paraview} (set output.animation or \
                             output.viewer to true)"
                        ),
                    );
                }
            }
        }
        unused
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn warnings(sets: &[&str], used: Use) -> Vec<String> {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let loaded = Config::load_given(None, &sets).unwrap();
        loaded.ineffective(used).iter().map(ToString::to_string).collect()
    }

    #[test]
    fn a_torque_key_without_a_profile_names_the_key_its_value_and_the_profiles() {
        assert_eq!(
            warnings(&["torque.amplitude=2"], Use::Run),
            [
                "torque.amplitude = 2 has no effect: no torque profile is set (set torque.profile to one of \
                 \"constant\", \"step\", \"ramp\", \"sine\" or \"table\")"
            ]
        );
        assert_eq!(
            warnings(&["torque.profile=\"step\"", "torque.duration=0.5"], Use::Run),
            [
                "torque.duration = 0.5 has no effect: torque.profile = \"step\" does not use it (set torque.profile \
              to \"ramp\")"
            ]
        );
        // the stepper's tau input turns as torque.follower says
        assert!(warnings(&["torque.follower=false"], Use::Stepper).is_empty());
        assert_eq!(warnings(&["torque.follower=false"], Use::Run).len(), 1);
    }

    #[test]
    fn wall_contact_and_reduced_body_keys_warn_where_they_do_not_act() {
        let w = warnings(&["contact.stiffness=1e10", "wall.face_size=0.002"], Use::Run);
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w.iter().all(|w| w.contains("there is no wall (set wall.kind to")),
            "{w:?}"
        );
        let w = warnings(&["wall.kind=\"rigid\"", "wall.face_size=0.002"], Use::Run);
        assert!(
            w.len() == 1 && w[0].contains("set wall.kind to \"deformable\""),
            "{w:?}"
        );
        let w = warnings(&["model.modes=4"], Use::Run);
        assert!(
            w.len() == 1 && w[0].starts_with("model.modes = 4 has no effect: the full body"),
            "{w:?}"
        );
        assert!(warnings(&["model.kind=\"reduced\"", "model.modes=4"], Use::Run).is_empty());
        // without a wall a stepper still measures its gap to the plane x = wall.x
        assert!(warnings(&["wall.x=-0.07"], Use::Stepper).is_empty());
        assert_eq!(warnings(&["wall.x=-0.07"], Use::Run).len(), 1);
    }

    #[test]
    fn keys_that_act_and_defaults_warn_of_nothing() {
        assert!(warnings(&[], Use::Run).is_empty());
        assert!(warnings(&[], Use::Stepper).is_empty());
        let acting = [
            "torque.profile=\"sine\"",
            "torque.amplitude=1",
            "torque.frequency=2",
            "torque.phase=0.5",
            "torque.start=0.1",
            "wall.kind=\"deformable\"",
            "wall.face_size=0.002",
            "contact.stiffness=1e10",
            "time.max_rotation_deg=2",
        ];
        let w = warnings(&acting, Use::Run);
        assert_eq!(w, ["time.max_rotation_deg = 2 has no effect: time.scheme = \"energy-momentum\" splits no step by its rotation (set time.scheme to \"trapezoidal\" or \"hht\")"]);
        // the file `pendulum-fem init` writes names only keys that act in it
        let dir = std::env::temp_dir().join(format!("pendulum-fem-ineffective-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("default.toml");
        std::fs::write(&file, super::super::commented_default()).unwrap();
        let loaded = Config::load_given(Some(&file), &[]).unwrap();
        assert!(loaded.given.iter().count() > 30, "the file names the keys");
        let w: Vec<String> = loaded.ineffective(Use::Run).iter().map(ToString::to_string).collect();
        assert!(w.is_empty(), "{w:#?}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn every_key_a_rule_names_is_a_configuration_key() {
        let json = serde_json::to_value(Config::default()).unwrap();
        let mut configs = vec![Config::default()];
        let mut c = Config::default();
        c.torque.profile = TorqueProfile::Sine;
        c.wall.kind = WallKind::Rigid;
        c.contact.method = ContactMethod::Penalty;
        c.model.kind = ModelKind::Reduced;
        c.mesh.file = Some("m.msh".into());
        c.output.animation = false;
        c.output.viewer = false;
        c.output.paraview = false;
        configs.push(c);
        for cfg in configs {
            for used in [Use::Run, Use::Stepper] {
                for (keys, _) in cfg.unused_keys(used) {
                    for key in keys {
                        let (section, name) = key.split_once('.').unwrap();
                        assert!(json[section].get(name).is_some(), "{key} is no configuration key");
                    }
                }
            }
        }
    }
}
