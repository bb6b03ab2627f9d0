//! Command-line interface of pendulum-fem.
use std::process::ExitCode;

fn main() -> ExitCode {
    eprintln!("pendulum-fem: not yet implemented");
    ExitCode::FAILURE
}
