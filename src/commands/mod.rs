//! The subcommands of the `pendulum-fem` binary, as library functions (the binary only parses
//! arguments and prints errors).

pub mod bench;
pub mod mesh;
pub mod modes;
/// `run`: the run driver, the crate `pendulum-fem-run` (used by the Python package and the sweeps
/// too); the command attaches the pictures ([`crate::render::pictures`]) and the progress bar.
pub use pendulum_fem_run as run;
pub mod summary;
pub mod sweep;
