//! Runs the `mesh` command on the tutorial configuration until the CLI calls it.
//!
//! `cargo run --release --example mesh_command [out_dir] [--json]`
use std::path::PathBuf;

fn main() -> Result<(), pendulum_fem::Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let json = args.iter().any(|a| a == "--json");
    let out = args
        .iter()
        .find(|a| !a.starts_with("--"))
        .map(PathBuf::from)
        .unwrap_or_else(|| "results/mesh".into());
    pendulum_fem::commands::mesh::mesh_command(&pendulum_fem::Config::default(), &out, json)
}
