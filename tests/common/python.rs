//! Python for the tests that run it (`tests/python_package.rs`, `tests/notebooks.rs`,
//! `tests/docs.rs`): the test environment of `scripts/test-env` (maturin, and the tools the FMU's
//! tests use), the wheel of `crates/python` built with its maturin, and the clean environment of
//! `scripts/wheel-env` into which that wheel is installed as a user would install it.

#![allow(dead_code)]
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// Runs `cmd` and returns its stdout; panics with everything it printed when it fails.
pub fn run(cmd: &mut Command, what: &str) -> String {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot start {cmd:?}: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.success(),
        "{what} failed ({}):\n--- stdout ---\n{stdout}\n--- stderr ---\n{stderr}",
        out.status
    );
    stdout
}

/// The interpreter that the script `scripts/<script>` prints (it makes or reuses its virtual
/// environment first).
fn env_python(root: &Path, script: &str) -> PathBuf {
    let python = run(&mut Command::new(root.join("scripts").join(script)), script);
    let python = PathBuf::from(python.trim());
    assert!(
        python.is_file(),
        "scripts/{script} printed `{}`, not a Python",
        python.display()
    );
    python
}

/// The interpreter of `scripts/test-env` (a virtual environment in `target/test-venv` with the
/// pinned test requirements, created on first use).
pub fn test_env_python(root: &Path) -> PathBuf {
    env_python(root, "test-env")
}

/// The wheel of `crates/python`, built once per test process with the test environment's maturin
/// (release) into a folder of its own, so that every test that installs it installs the same
/// file and none rebuilds it. The extension is built for the stable ABI (pyo3's `abi3-py39`), so
/// the one wheel serves CPython 3.9 and later: its name says `cp39-abi3`.
pub fn wheel(root: &Path) -> &'static Path {
    static WHEEL: OnceLock<PathBuf> = OnceLock::new();
    WHEEL.get_or_init(|| build_wheel(root, &super::scratch("wheel")))
}

/// Builds the wheel into a fresh `scratch/wheels` and returns it.
fn build_wheel(root: &Path, scratch: &Path) -> PathBuf {
    let python = test_env_python(root);
    let wheels = scratch.join("wheels");
    let _ = std::fs::remove_dir_all(&wheels);
    run(
        Command::new(&python)
            .args(["-m", "maturin", "build", "--release", "--quiet", "--manifest-path"])
            .arg(root.join("crates/python/Cargo.toml"))
            .arg("--out")
            .arg(&wheels),
        "maturin build",
    );
    let wheel = std::fs::read_dir(&wheels)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "whl"))
        .expect("maturin wrote a wheel");
    let name = wheel.file_name().unwrap().to_string_lossy().into_owned();
    assert!(
        name.starts_with("pendulum_fem-") && name.contains("-cp39-abi3-"),
        "the wheel is not the package's abi3 wheel for CPython >= 3.9: {name}"
    );
    wheel
}

/// Installs [`wheel`] into the test environment (`scripts/test-env`), once per test process,
/// replacing any earlier build, so that the package imported there is this checkout's; returns
/// that environment's interpreter.
pub fn test_env_with_wheel(root: &Path) -> &'static Path {
    static INSTALLED: OnceLock<PathBuf> = OnceLock::new();
    INSTALLED.get_or_init(|| {
        let python = test_env_python(root);
        run(
            Command::new(&python)
                .args(["-m", "pip", "install", "--quiet", "--force-reinstall", "--no-deps"])
                .arg(wheel(root)),
            "pip install",
        );
        python
    })
}

/// A clean virtual environment with this checkout's wheel installed, as a user installs it.
pub struct WheelEnv {
    /// Its interpreter.
    pub python: PathBuf,
    /// The wheel's file name (`pendulum_fem-…-cp39-abi3-….whl`).
    pub wheel: String,
}

impl WheelEnv {
    /// A command running `program` (a path, or a name found on the environment's `PATH`) in this
    /// environment: its `bin/` first on `PATH`, then only the system's folders (no cargo, rustc or
    /// other interpreter's tools), no `PYTHONPATH`, working folder `cwd`.
    pub fn command(&self, program: impl AsRef<std::ffi::OsStr>, cwd: &Path) -> Command {
        let mut path = OsString::from(self.python.parent().unwrap());
        path.push(":/usr/local/bin:/usr/bin:/bin");
        let mut cmd = Command::new(program);
        cmd.env("PATH", path)
            .env("VIRTUAL_ENV", self.python.parent().unwrap().parent().unwrap())
            .env_remove("PYTHONPATH")
            .env_remove("PYTHONHOME")
            .current_dir(cwd);
        cmd
    }
}

/// The clean environment of `scripts/wheel-env` (`target/wheel-venv`: made anew when
/// `scripts/requirements-wheel.txt` changes, which pins everything the tests and notebooks import;
/// it never holds maturin or any other build tool) with [`wheel`] installed, with its extras
/// (`sweep`, `dask`, `syssimx`, `test`), once per test process: every test that uses it sees the
/// same installation, and none reinstalls it under another's feet. Checks that pip's requirements
/// hold and that `pendulum_fem` imports from the environment, not from the source tree, from a
/// working folder outside the source tree.
pub fn wheel_env(root: &Path) -> &'static WheelEnv {
    static ENV: OnceLock<WheelEnv> = OnceLock::new();
    ENV.get_or_init(|| install_into_wheel_env(root))
}

fn install_into_wheel_env(root: &Path) -> WheelEnv {
    let wheel = wheel(root);
    let env = WheelEnv {
        python: env_python(root, "wheel-env"),
        wheel: wheel.file_name().unwrap().to_string_lossy().into_owned(),
    };
    let venv = env.python.parent().unwrap().parent().unwrap().to_path_buf();
    for tool in ["maturin", "cargo", "rustc", "zig"] {
        assert!(
            !venv.join("bin").join(tool).exists(),
            "the clean environment {} has {tool}",
            venv.display()
        );
    }
    let cwd = outside_the_source_tree("wheel-env");
    let pip = |args: &[&str], what: &str| {
        let mut cmd = env.command(&env.python, &cwd);
        cmd.args(["-m", "pip", "--disable-pip-version-check"]).args(args);
        run(&mut cmd, what)
    };
    pip(&["uninstall", "--quiet", "--yes", "pendulum-fem"], "pip uninstall");
    let with_extras = format!("{}[sweep,dask,syssimx,test]", wheel.display());
    pip(&["install", "--quiet", &with_extras], "pip install of the wheel");
    pip(&["check"], "pip check");
    let mut cmd = env.command(&env.python, &cwd);
    cmd.args(["-c", "import pendulum_fem; print(pendulum_fem.__file__)"]);
    let imported = PathBuf::from(run(&mut cmd, "import pendulum_fem").trim());
    assert!(
        imported.starts_with(&venv),
        "pendulum_fem imported from {}, not from the environment {}",
        imported.display(),
        venv.display()
    );
    let _ = std::fs::remove_dir_all(&cwd);
    env
}

/// Packs `dir/PendulumFem.fmu` from the FMU's shared object that cargo built with the calling test
/// (`pendulum-fem-fmu` is a dev-dependency of the root package), as `cargo xtask fmu` packs it.
pub fn pack_fmu(dir: &Path) -> PathBuf {
    use pendulum_fem_fmu::package::{write_fmu, LIBRARY_FILE};
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap();
    let library = [deps.join(LIBRARY_FILE), deps.join("..").join(LIBRARY_FILE)]
        .into_iter()
        .find(|p| p.is_file())
        .unwrap_or_else(|| panic!("{LIBRARY_FILE} not found next to {}", exe.display()));
    let fmu = dir.join("PendulumFem.fmu");
    write_fmu(&library, &fmu).expect("FMU packed");
    fmu
}

/// A fresh, empty folder `pendulum-fem-<name>-<process id>-<call>` in the system's temporary
/// folder: a working folder outside the source tree (the caller removes it when done).
pub fn outside_the_source_tree(name: &str) -> PathBuf {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    let dir = std::env::temp_dir().join(format!("pendulum-fem-{name}-{}-{call}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs the CLI built with the calling test (`pendulum-fem run`, the default configuration with the
/// overrides `sets`, no pictures, animations, ParaView files or viewer) into a fresh folder `out`,
/// and returns it (`results.csv`, and `events.csv` with a wall).
pub fn cli_run(out: &Path, sets: &[&str]) -> PathBuf {
    let _ = std::fs::remove_dir_all(out);
    let mut cmd = super::bin();
    cmd.args(["run", "--quiet"]);
    for set in sets {
        cmd.args(["--set", set]);
    }
    for key in ["plots", "animation", "paraview", "viewer"] {
        cmd.args(["--set", &format!("output.{key}=false")]);
    }
    run(cmd.arg("--out").arg(out), "pendulum-fem run");
    out.to_path_buf()
}
