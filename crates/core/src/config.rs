//! Run configuration: every tunable with its default, unit and allowed range.
//!
//! The configuration is TOML. Every key is optional; the defaults are the model of the NGSolve
//! tutorial "FEM Pendulum: Basics" stepped by the energy-momentum scheme from the rigid-body start
//! (`time.scheme = "trapezoidal"` with `initial.acceleration = "zero"` is the tutorial's run).
//! Overrides from the command line (`--set mesh.max_size=0.01`) are merged into the TOML document
//! before it is deserialised, so they are checked exactly like file values.
//!
//! **Mistakes** are all reported at once, in the order they were written (by line in the file,
//! then the `--set` overrides in their order): unknown keys (serde `deny_unknown_fields`) named
//! with their place and the nearest allowed key, values of the wrong type, and every value out of
//! range ([`Config::validate`]), each message naming the key (`mesh.max_size`) and the allowed
//! range.
//!
//! **Keys without effect**: the keys the file and the overrides named are kept with the
//! configuration ([`Config::load_given`], [`GivenKeys`]), and [`Config::ineffective_keys`] names
//! those that the configuration does not use, with what would make them act: the one rule the
//! CLI, the Python package and the FMU warn by.
//!
//! All quantities are SI: metres, kilograms, seconds, pascals, newtons, radians unless a key says
//! `_deg`.
//!
//! **Files**: one per section or pair of sections (`geometry`: `[geometry]`, `[mesh]`; `material`:
//! `[material]`, `[gravity]`; `initial`; `time`: `[time]`, `[solver]`; `torque`; `wall`: `[wall]`,
//! `[contact]`; `output`; `model`), `ranges` (the range checks and the report of the mistakes),
//! `read` (files and text), `overrides` (`--set`), `given` (the keys given and where),
//! `ineffective` (the keys without effect), `unknown_key` (the message for a misspelled key); the
//! commented default file is `default_config.toml` ([`commented_default`]).

use serde::{Deserialize, Serialize};

mod geometry;
mod given;
mod ineffective;
mod initial;
mod material;
mod model;
mod output;
mod overrides;
mod ranges;
mod read;
mod time;
mod torque;
mod unknown_key;
mod wall;

pub use geometry::{Geometry, MeshConfig, MeshSizes};
pub use given::{leaf_keys, GivenKey, GivenKeys, Place};
pub use ineffective::{Ineffective, Use};
pub use initial::{Initial, InitialAcceleration, InitialElastic};
pub use material::{Gravity, Material, MaterialModel, Plane};
pub use model::{ModelConfig, ModelKind, MAX_MODES};
pub use output::Output;
pub use read::{Loaded, PATH_KEYS};
pub use time::{Cutbacks, Scheme, Solver, StepPlan, Time};
pub use torque::{Torque, TorqueProfile};
pub use unknown_key::reports_an_unknown_key;
pub use wall::{Contact, ContactMethod, Wall, WallKind};

/// The whole configuration, one section per pipeline stage.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Config {
    /// Shape of the pendulum.
    pub geometry: Geometry,
    /// Mesh sizes and element order.
    pub mesh: MeshConfig,
    /// Constitutive law and its parameters.
    pub material: Material,
    /// Gravity.
    pub gravity: Gravity,
    /// Initial state.
    pub initial: Initial,
    /// Time stepping.
    pub time: Time,
    /// Newton solver.
    pub solver: Solver,
    /// Actuator torque at the pivot.
    pub torque: Torque,
    /// The wall the head strikes (the contact tutorial).
    pub wall: Wall,
    /// Contact between the head and the wall.
    pub contact: Contact,
    /// What a run writes.
    pub output: Output,
    /// The full finite-element body or the reduced one.
    pub model: ModelConfig,
}

/// A commented configuration listing every key with its default and unit.
pub fn commented_default() -> String {
    include_str!("default_config.toml").to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commented_default_parses_to_the_defaults() {
        let cfg = Config::from_toml_str(&commented_default()).expect("the shipped default config is valid");
        assert_eq!(cfg, Config::default());
    }
}
