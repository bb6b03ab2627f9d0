//! The subcommands of the `pendulum-fem` binary, as library functions (the binary only parses
//! arguments and prints errors).

pub mod bench;
pub mod mesh;
/// `run`: the run driver, in `pendulum-fem-io` (used by the Python package and the sweeps too).
pub use pendulum_fem_io::run;
pub mod sweep;
