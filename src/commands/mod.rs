//! Subcommands of the command-line interface, each a library function the binary calls.

pub mod mesh;
