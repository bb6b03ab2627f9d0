//! Build tasks of pendulum-fem, run as `cargo xtask <task>` (an alias in `.cargo/config.toml`).
//!
//! * `fmu`: builds the FMU's shared object in release mode (`cargo build --release -p
//!   pendulum-fem-fmu`) and packs it with the generated `modelDescription.xml` into
//!   `target/fmu/PendulumFem.fmu`.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

use pendulum_fem_fmu::package::{write_fmu, LIBRARY_FILE};

fn main() -> ExitCode {
    let task = std::env::args().nth(1);
    let result = match task.as_deref() {
        Some("fmu") => fmu(),
        _ => Err("usage: cargo xtask fmu   (builds target/fmu/PendulumFem.fmu)".to_string()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The workspace root (the parent of this crate's folder).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lies in the workspace root")
        .to_path_buf()
}

/// The target folder: `CARGO_TARGET_DIR` if set, else `target/` in the workspace root.
fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("target"))
}

fn fmu() -> Result<(), String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = Command::new(cargo)
        .args(["build", "--release", "-p", "pendulum-fem-fmu"])
        .current_dir(root())
        .status()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if !status.success() {
        return Err(format!("cargo build --release -p pendulum-fem-fmu failed ({status})"));
    }
    let target = target_dir();
    let library = target.join("release").join(LIBRARY_FILE);
    let fmu = target.join("fmu").join("PendulumFem.fmu");
    write_fmu(&library, &fmu).map_err(|e| format!("writing {}: {e}", fmu.display()))?;
    println!("{}", fmu.display());
    Ok(())
}
