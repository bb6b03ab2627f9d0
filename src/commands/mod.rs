//! The subcommands of the `pendulum-fem` binary, as library functions (the binary only parses
//! arguments and prints errors).

pub mod bench;
pub mod mesh;
pub mod run;
pub mod sweep;
