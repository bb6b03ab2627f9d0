//! The FMU that `cargo xtask fmu` ships is portable: its shared object carries no debug info, the
//! archive is small, it needs at most glibc 2.17, and fmpy still validates and simulates it.
//!
//! The test runs `cargo xtask fmu` itself (the `fmu-release` profile, linked by cargo-zigbuild
//! against glibc 2.17), with the test environment's `bin/` first on `PATH`: `scripts/test-env`
//! installs `ziglang` and `cargo-zigbuild` there with fmpy. Its first run builds the dependencies
//! in that profile (a few minutes on 2 cores); later runs relink only.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The largest archive accepted: the bound (the FMU's shared object is stripped and built
/// without debug info to stay below it).
const MAX_ZIPPED: u64 = 3_000_000;

/// The newest glibc symbol version the shared object may need: glibc 2.17 (2012, RHEL 7).
const MAX_GLIBC: (u32, u32) = (2, 17);

fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .expect("the workspace root exists")
}

/// Runs `cmd`; panics with what it printed when it fails. Returns stdout.
fn run(cmd: &mut Command, what: &str) -> String {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot start {cmd:?}: {e}"));
    assert!(
        out.status.success(),
        "{what} failed ({}):\n--- stdout ---\n{}\n--- stderr ---\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The `GLIBC_x.y` versions the dynamic symbols of `so` need (`objdump -T`), as numbers.
fn glibc_versions(so: &Path) -> Vec<(u32, u32)> {
    let table = run(Command::new("objdump").arg("-T").arg(so), "objdump -T");
    let mut versions: Vec<(u32, u32)> = table
        .split("GLIBC_")
        .skip(1)
        .filter_map(|rest| {
            let v: String = rest.chars().take_while(|c| c.is_ascii_digit() || *c == '.').collect();
            let mut parts = v.split('.').map(|p| p.parse::<u32>().ok());
            Some((parts.next()??, parts.next().flatten().unwrap_or(0)))
        })
        .collect();
    versions.sort_unstable();
    versions.dedup();
    versions
}

/// The names of the ELF sections of `so` (`objdump -h`).
fn sections(so: &Path) -> Vec<String> {
    let table = run(Command::new("objdump").arg("-h").arg(so), "objdump -h");
    table
        .lines()
        .filter_map(|l| {
            let mut words = l.split_whitespace();
            let index = words.next()?;
            index.parse::<usize>().ok()?;
            words.next().map(str::to_string)
        })
        .collect()
}

#[test]
fn the_shipped_fmu_is_stripped_small_needs_at_most_glibc_2_17_and_fmpy_runs_it() {
    let root = workspace_root();
    let python = PathBuf::from(run(&mut Command::new(root.join("scripts/test-env")), "scripts/test-env").trim());
    let venv_bin = python.parent().unwrap().to_path_buf();
    let path = std::env::join_paths(
        std::iter::once(venv_bin).chain(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())),
    )
    .unwrap();
    let cargo = option_env!("CARGO").unwrap_or("cargo");
    let out = Command::new(cargo)
        .args(["xtask", "fmu"])
        .current_dir(&root)
        .env("PATH", &path)
        .output()
        .expect("cargo xtask fmu starts");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "cargo xtask fmu failed:\n{stderr}");
    assert!(
        !stderr.contains("cargo-zigbuild not found"),
        "the test environment has cargo-zigbuild, so the FMU is linked against glibc 2.17:\n{stderr}"
    );
    let fmu = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    assert!(fmu.ends_with("target/fmu/PendulumFem.fmu"), "{}", fmu.display());

    let zipped = std::fs::metadata(&fmu).unwrap().len();
    assert!(zipped < MAX_ZIPPED, "{} is {zipped} bytes zipped", fmu.display());

    // the shared object, as an importer unpacks it
    let mut archive = zip::ZipArchive::new(std::fs::File::open(&fmu).unwrap()).unwrap();
    let mut entry = archive.by_name("binaries/linux64/PendulumFem.so").unwrap();
    let so = fmu.with_file_name("PendulumFem-unpacked.so");
    std::io::copy(&mut entry, &mut std::fs::File::create(&so).unwrap()).unwrap();
    let debug: Vec<String> = sections(&so).into_iter().filter(|s| s.starts_with(".debug")).collect();
    assert!(debug.is_empty(), "debug sections in the FMU's library: {debug:?}");
    let glibc = glibc_versions(&so);
    assert!(
        !glibc.is_empty(),
        "no GLIBC_ symbol versions found: is {} a glibc library?",
        so.display()
    );
    let newest = *glibc.last().unwrap();
    assert!(
        newest <= MAX_GLIBC,
        "the FMU needs GLIBC_{}.{} ({glibc:?})",
        newest.0,
        newest.1
    );
    // the FMI functions are still exported
    let exports = run(Command::new("objdump").arg("-T").arg(&so), "objdump -T");
    for f in ["fmi2Instantiate", "fmi2DoStep", "fmi2GetReal", "fmi2SerializeFMUstate"] {
        assert!(exports.contains(f), "{f} is not exported");
    }

    // fmpy validates and runs it: the default swing from 20° reaches θ < 0 by its half period
    let script = format!(
        "from fmpy import simulate_fmu\nfrom fmpy.validation import validate_fmu\n\
         problems = validate_fmu({fmu:?})\nassert not problems, problems\n\
         r = simulate_fmu({fmu:?}, stop_time=0.5, output_interval=0.01)\n\
         print(r['theta'][0], r['theta'][-1])\n\
         assert abs(r['theta'][0] - 0.3490658503988659) < 1e-6 and r['theta'][-1] < -0.3, r['theta'][-1]\n",
        fmu = fmu.display().to_string()
    );
    run(Command::new(&python).args(["-c", &script]), "fmpy with the shipped FMU");
}
