//! Build tasks of pendulum-fem, run as `cargo xtask <task>` (an alias in `.cargo/config.toml`).
//!
//! * `fmu`: builds the FMU's shared object with the `fmu-release` profile (release code, no debug
//!   info, symbols stripped: the FMI functions stay exported) and packs it with the generated
//!   `modelDescription.xml` into `target/fmu/PendulumFem.fmu`. With `cargo zigbuild` installed
//!   (`pip install ziglang cargo-zigbuild`) it links against glibc 2.17
//!   (`--target x86_64-unknown-linux-gnu.2.17`), so the FMU loads on Linux systems from 2014 on;
//!   without it the FMU needs the glibc of the building machine, which it says.
//! * `fmu --fmi 3`: the same shared object packed as the FMI 3.0 FMU `target/fmu/PendulumFem3.fmu`
//!   (model identifier `PendulumFem3`, `binaries/x86_64-linux/PendulumFem3.so`); `--fmi 2` is the
//!   default.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

use pendulum_fem_fmu::package::{write_fmu, write_fmu3, LIBRARY_FILE};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match args.as_slice() {
        ["fmu"] | ["fmu", "--fmi", "2"] => fmu(2),
        ["fmu", "--fmi", "3"] => fmu(3),
        ["fmu", "--fmi", other] => Err(format!("--fmi {other}: allowed 2 (the default) or 3")),
        _ => Err(
            "usage: cargo xtask fmu [--fmi 2|3]   (builds target/fmu/PendulumFem.fmu, or PendulumFem3.fmu with --fmi 3)"
                .to_string(),
        ),
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

/// The cargo profile of the FMU's shared object (the workspace's `Cargo.toml`).
const PROFILE: &str = "fmu-release";

/// The target of a portable build: the host's, linked against glibc 2.17 by cargo-zigbuild.
const PORTABLE_TARGET: &str = "x86_64-unknown-linux-gnu.2.17";

/// Builds the shared object and packs the FMU of FMI version `version` (2 or 3).
fn fmu(version: u8) -> Result<(), String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let zigbuild = Command::new(&cargo)
        .args(["zigbuild", "--help"])
        .output()
        .is_ok_and(|o| o.status.success());
    let mut args = vec![if zigbuild { "zigbuild" } else { "build" }, "--profile", PROFILE];
    if zigbuild {
        args.extend(["--target", PORTABLE_TARGET]);
    } else {
        eprintln!(
            "xtask: cargo-zigbuild not found, so the FMU needs this machine's glibc; for one that loads on glibc \
             2.17 and later: pip install ziglang cargo-zigbuild"
        );
    }
    args.extend(["-p", "pendulum-fem-fmu"]);
    let status = Command::new(&cargo)
        .args(&args)
        .current_dir(root())
        .status()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if !status.success() {
        return Err(format!("cargo {} failed ({status})", args.join(" ")));
    }
    let target = target_dir();
    let library = match zigbuild {
        // cargo-zigbuild writes to the target's folder without the glibc suffix
        true => target.join("x86_64-unknown-linux-gnu").join(PROFILE),
        false => target.join(PROFILE),
    }
    .join(LIBRARY_FILE);
    let (name, write): (_, fn(&Path, &Path) -> std::io::Result<()>) = match version {
        3 => ("PendulumFem3.fmu", write_fmu3),
        _ => ("PendulumFem.fmu", write_fmu),
    };
    let fmu = target.join("fmu").join(name);
    write(&library, &fmu).map_err(|e| format!("writing {}: {e}", fmu.display()))?;
    println!("{}", fmu.display());
    Ok(())
}
