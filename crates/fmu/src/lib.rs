//! # pendulum-fem-fmu
//!
//! The deformable pendulum of `pendulum-fem` as an FMI 2.0 Co-Simulation FMU, model identifier
//! `PendulumFem` (and, from the same shared object, as the FMI 3.0 Co-Simulation FMU
//! `PendulumFem3`, which reports wall impacts as events): a torque input `tau` at the pivot; outputs θ, ω, α, the wall gap and contact
//! outputs, the total energy; parameters for the start, the material, the geometry, the mesh and
//! the solver, with the CLI's defaults. `cargo xtask fmu` writes `target/fmu/PendulumFem.fmu`.
//!
//! * [`variables`]: the one table of variables, and `modelDescription.xml` generated from it.
//! * [`instance`]: an FMU instance in safe Rust (state machine, parameters as configuration
//!   overrides, `doStep` over the stepper, FMU states as snapshots).
//! * [`contact`]: the one function that reads the wall and contact outputs.
//! * `ffi`: the C boundary both FMI versions share, panic-free: one implementation of every call
//!   they have in common (instantiation, freeing, reset, values, FMU states, refusals).
//! * `fmi2`: the exported `fmi2*` C functions (every one of the standard's), thin adapters onto
//!   `ffi` and the instance.
//! * `fmi3`: the exported `fmi3*` C functions of the FMI 3.0 FMU `PendulumFem3` (every one of
//!   `fmi3Functions.h`), likewise; event mode and early return at impacts are FMI 3.0's own.
//! * [`package`]: the zip archive (used by `xtask` and the tests).
#![warn(missing_docs)]

pub mod contact;
mod ffi;
mod fmi2;
mod fmi3;
pub mod instance;
pub mod package;
pub mod variables;

pub use instance::{FmuState, Instance, Status};
pub use variables::{model_description, model_description_fmi3, MODEL_IDENTIFIER, MODEL_IDENTIFIER_FMI3, VARIABLES};
