//! `pendulum-fem bench`: measured speed and memory (benchmarks, never timed unit tests).
//!
//! * `run`: the whole default job (mesh, 100 steps, post-processing, `results.csv`) repeated, with
//!   a breakdown per Newton iteration (assembly, factorisation, solve), for the configured scheme
//!   and the other family for comparison; with `--ngsolve PYTHON` the NGSolve script of the
//!   tutorial's pendulum (`--anchor`, default `scripts/ngsolve/pendulum_basics.py`, shipped here) is
//!   run tuned and as written in the same session and the ratios of wall times are printed.
//! * `scaling`: time per step at about 5k, 20k, 80k and 320k unknowns (all mesh sizes scaled by a
//!   common factor found by probing the mesher).
//! * `mesh`: the tutorial mesh (best of 10) and a mesh of about `--triangles` triangles.
//! * `torque`: 100 steps with and without a follower torque (the cost of the term).
//! * `memory`: resident memory after 100 and after 1000 steps (streaming output must keep it flat).
//! * `modes`: 20 elastic modes of the pendulum (and the rigid one), the eigensolver alone and
//!   with the stiffness at rest ([`bench_modes`]).
//! * `fmu`: the FMU (`cargo xtask fmu`, or `--fmu FILE`) driven by fmpy through
//!   `crates/fmu/examples/fmpy_speed.py` (`setReal(tau)`, `doStep`, every output read, each step)
//!   with the interpreter of `scripts/test-env` (or `--python`): the real-time factor
//!   `simulated time / wall time` at communication steps of 10 ms and 1 ms.
//! * `reduced`: the reduced body against the full model, the bare stepper at 1 ms and the default
//!   job, its set-up computed and read from the disk cache ([`reduced`]).

use std::path::{Path, PathBuf};
use std::time::Instant;

pub mod reduced;
pub use reduced::{bench_reduced, ReducedBench};

use crate::commands::run::{run_with, RunOptions, RunSummary};
use crate::config::Scheme;
use crate::mesh::bench::scaled_config;
use crate::simulation::Simulation;
use crate::{mesh, Config, Error};

/// Resident set size of this process \[MiB\] (Linux; `None` elsewhere).
pub fn resident_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

fn temp_dir(tag: &str) -> Result<PathBuf, Error> {
    let dir = std::env::temp_dir().join(format!("pendulum-fem-bench-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    Ok(dir)
}

/// One default run into a scratch folder.
pub fn time_default_run(cfg: &Config) -> Result<RunSummary, Error> {
    // a whole run meshes and builds its operators, as a fresh process does
    crate::mesh::forget_last();
    crate::simulation::forget_shared();
    let dir = temp_dir("run")?;
    let opts = RunOptions {
        config: cfg.clone(),
        out: Some(dir.clone()),
        force: true,
        ..Default::default()
    };
    let s = run_with(&opts, dir.clone(), |_, _| Ok(()));
    let _ = std::fs::remove_dir_all(&dir);
    s
}

/// Repeats the run of `cfg` and returns the fastest.
fn best_run(cfg: &Config, repeats: usize) -> Result<RunSummary, Error> {
    let mut best: Option<RunSummary> = None;
    for i in 0..repeats.max(1) {
        let s = time_default_run(cfg)?;
        println!(
            "  run {}: total {:.3} s (mesh {:.4} s, set-up {:.4} s, steps+post+csv {:.3} s), {} Newton iterations",
            i + 1,
            s.seconds_total,
            s.seconds_mesh,
            s.seconds_setup,
            s.seconds_steps,
            s.newton_iterations
        );
        if best.as_ref().is_none_or(|b| s.seconds_total < b.seconds_total) {
            best = Some(s);
        }
    }
    Ok(best.expect("at least one run"))
}

/// Prints the best run and its breakdown per Newton iteration.
fn print_breakdown(s: &RunSummary, repeats: usize) {
    let t = s.timings;
    let its = s.newton_iterations.max(1) as f64;
    println!(
        "  best of {repeats}: {:.3} s for {} steps, {} unknowns; {:.2} Newton iterations per step, {} factorisations",
        s.seconds_total,
        s.steps,
        s.unknowns,
        its / s.steps.max(1) as f64,
        s.factorizations
    );
    println!("  per Newton iteration:");
    println!(
        "    assembly (energy, gradient, tangent) {:.3} ms",
        1e3 * t.assembly / its
    );
    println!(
        "    numeric factorisation               {:.3} ms",
        1e3 * t.factorization / its
    );
    println!("    solves + Schur complement           {:.3} ms", 1e3 * t.solve / its);
    println!(
        "    gradient evaluations (no tangent)   {:.3} ms",
        1e3 * t.residual / its
    );
    println!(
        "    line search                         {:.3} ms",
        1e3 * t.line_search / its
    );
    let newton = t.assembly + t.factorization + t.solve + t.residual + t.line_search;
    println!(
        "  totals: assembly {:.3} s, factorisation {:.3} s, solve {:.3} s, gradients {:.3} s; outside Newton \
         (set-up, predictor, post-processing, CSV) {:.3} s",
        t.assembly,
        t.factorization,
        t.solve,
        t.residual,
        s.seconds_total - newton
    );
}

/// Runs the NGSolve script with `args` and returns its wall time (process start to exit) \[s\].
fn time_ngsolve(python: &Path, anchor: &Path, args: &[&str]) -> Result<f64, Error> {
    let start = Instant::now();
    let out = std::process::Command::new(python)
        .arg(anchor)
        .args(args)
        .output()
        .map_err(|e| Error::io(python, e))?;
    let seconds = start.elapsed().as_secs_f64();
    if !out.status.success() {
        return Err(Error::Input(format!(
            "NGSolve script {} {} failed: {}",
            anchor.display(),
            args.join(" "),
            String::from_utf8_lossy(&out.stderr)
        )));
    }
    Ok(seconds)
}

/// `bench run`: the run of `cfg` with its scheme and, for comparison, with the other family
/// (energy-momentum against trapezoidal), each repeated, best reported with its breakdown;
/// optionally the NGSolve tutorial script, tuned (`--post 0 --energy 0 --compile 1 --threads 2`:
/// compiled Variation, TaskManager, two threads) and as written (`--post 1 --energy 0`), in the
/// same session, with the ratios of wall times.
pub fn bench_run(cfg: &Config, repeats: usize, ngsolve_python: Option<&Path>, anchor: &Path) -> Result<(), Error> {
    if let Some(python) = ngsolve_python {
        check_ngsolve_inputs(python, anchor)?;
    }
    let other = match cfg.time.scheme {
        Scheme::EnergyMomentum => Scheme::Trapezoidal,
        _ => Scheme::EnergyMomentum,
    };
    println!("scheme {:?} (the configuration's):", cfg.time.scheme);
    let s = best_run(cfg, repeats)?;
    print_breakdown(&s, repeats);
    let mut other_cfg = cfg.clone();
    other_cfg.time.scheme = other;
    println!("scheme {other:?} (for comparison):");
    let o = best_run(&other_cfg, repeats)?;
    print_breakdown(&o, repeats);
    if let Some(python) = ngsolve_python {
        let tuned = time_ngsolve(
            python,
            anchor,
            &["--post", "0", "--energy", "0", "--compile", "1", "--threads", "2"],
        )?;
        let written = time_ngsolve(python, anchor, &["--post", "1", "--energy", "0"])?;
        println!("NGSolve tutorial script, tuned (--post 0 --energy 0 --compile 1 --threads 2): {tuned:.3} s wall");
        println!("NGSolve tutorial script as written (--post 1 --energy 0): {written:.3} s wall");
        println!(
            "speed ratio NGSolve / pendulum-fem ({:?}, {:.3} s): tuned {:.1}, as written {:.1}",
            cfg.time.scheme,
            s.seconds_total,
            tuned / s.seconds_total,
            written / s.seconds_total
        );
    }
    Ok(())
}

/// Fails, before any timing, when the NGSolve script is missing or `python` cannot import
/// `ngsolve`; the message names the path or the interpreter and what to pass instead.
pub fn check_ngsolve_inputs(python: &Path, anchor: &Path) -> Result<(), Error> {
    if !anchor.is_file() {
        return Err(Error::Config(format!(
            "--anchor {}: the NGSolve tutorial script is not there; pass its path with --anchor FILE",
            anchor.display()
        )));
    }
    let probe = std::process::Command::new(python)
        .args(["-c", "import ngsolve"])
        .output()
        .map_err(|e| Error::Config(format!("--ngsolve {}: cannot run it ({e})", python.display())))?;
    if !probe.status.success() {
        return Err(Error::Config(format!(
            "--ngsolve {}: this Python cannot import ngsolve ({}); pass a Python with NGSolve installed",
            python.display(),
            String::from_utf8_lossy(&probe.stderr)
                .lines()
                .last()
                .unwrap_or("")
                .trim()
        )));
    }
    Ok(())
}

/// The mesh-size factor whose mesh has about `target` unknowns (probes the mesher, which is cheap:
/// a graded mesh grows more slowly than `1/factor²`, so the factor is corrected a few times).
fn factor_for_unknowns(cfg: &Config, target: usize) -> Result<f64, Error> {
    let mut f = 1.0;
    for _ in 0..4 {
        let n = crate::Model::unknowns_of(&mesh::generate(&scaled_config(cfg, f))?);
        if (n as f64 / target as f64 - 1.0).abs() < 0.05 {
            break;
        }
        f *= (n as f64 / target as f64).powf(0.7);
    }
    Ok(f)
}

/// `bench scaling`: time per step for meshes of about 5k, 20k, 80k, 320k unknowns (up to `largest`).
pub fn bench_scaling(cfg: &Config, steps: usize, largest: usize) -> Result<(), Error> {
    println!(
        "{:>10} {:>10} {:>12} {:>12} {:>14} {:>12} {:>10}",
        "sizes x", "unknowns", "mesh s", "setup s", "ms/step", "its/step", "nnz(L)"
    );
    let mut previous: Option<(usize, f64)> = None;
    let mut target = 5_000;
    while target <= largest {
        let f = factor_for_unknowns(cfg, target)?;
        let c = scaled_config(cfg, f);
        let t0 = Instant::now();
        // the mesher itself, not a mesh kept on disk
        let m = mesh::generate_with_stats(&c)?.0;
        let t_mesh = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let mut sim = Simulation::from_config(&c, m)?;
        let t_setup = t1.elapsed().as_secs_f64();
        let t2 = Instant::now();
        for _ in 0..steps {
            sim.advance()?;
        }
        let per_step = t2.elapsed().as_secs_f64() / steps as f64;
        let n = sim.model.unknowns();
        println!(
            "{:>10.3} {:>10} {:>12.3} {:>12.3} {:>14.2} {:>12.2} {:>10}",
            f,
            n,
            t_mesh,
            t_setup,
            1e3 * per_step,
            sim.total_iterations as f64 / steps as f64,
            sim.factor_nnz()
        );
        if let Some((n0, t0)) = previous {
            println!(
                "{:>10} growth exponent (time ~ n^p): p = {:.2}",
                "",
                (per_step / t0).ln() / (n as f64 / n0 as f64).ln()
            );
        }
        previous = Some((n, per_step));
        target *= 4;
    }
    Ok(())
}

/// `bench memory`: resident memory after `short` and after `long` steps of the default model.
pub fn bench_memory(cfg: &Config, short: usize, long: usize) -> Result<(), Error> {
    for steps in [short, long] {
        let mut c = cfg.clone();
        c.time.end = steps as f64 * c.time.dt;
        let before = resident_mib().unwrap_or(f64::NAN);
        let s = time_default_run(&c)?;
        let after = resident_mib().unwrap_or(f64::NAN);
        println!(
            "{steps:>6} steps: {:.2} s, resident memory {before:.1} MiB before, {after:.1} MiB after",
            s.seconds_total
        );
    }
    Ok(())
}

/// CPU time (user + system) of this process so far \[s\] (Linux, 100 ticks per second; `None`
/// elsewhere). Less sensitive than wall time to other processes on a busy machine.
pub fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // fields after the parenthesised command name; utime and stime are fields 14 and 15
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Times of [`bench_torque`]: the same steps without and with the actuator torque.
#[derive(Clone, Debug, Default)]
pub struct TorqueBench {
    /// Steps timed per run.
    pub steps: usize,
    /// Best wall time of the steps without torque \[s\].
    pub seconds_without: f64,
    /// Best wall time of the steps with the follower torque \[s\].
    pub seconds_with: f64,
    /// Best CPU time (all threads) of the steps without and with torque \[s\].
    pub cpu_seconds: (f64, f64),
    /// Newton iterations without and with torque.
    pub iterations: (usize, usize),
    /// Stored entries of the Cholesky factor without and with torque.
    pub factor_nnz: (usize, usize),
}

impl TorqueBench {
    /// `seconds_with / seconds_without − 1`.
    pub fn overhead(&self) -> f64 {
        self.seconds_with / self.seconds_without - 1.0
    }
}

/// Times `steps` steps of `cfg` without torque and with a constant follower torque of `amplitude`
/// \[N m\] (set-up excluded), alternating, best of `repeats`; prints and returns the figures. With
/// `amplitude = 0` both runs follow the same motion (same Newton iterations), so the difference is
/// the cost of the term and of its denser pattern alone.
pub fn bench_torque(cfg: &Config, steps: usize, repeats: usize, amplitude: f64) -> Result<TorqueBench, Error> {
    let mut without = cfg.clone();
    without.torque = Default::default();
    let mut with = cfg.clone();
    with.torque.profile = crate::config::TorqueProfile::Constant;
    with.torque.amplitude = amplitude;
    with.torque.follower = true;
    let mut out = TorqueBench {
        steps,
        seconds_without: f64::INFINITY,
        seconds_with: f64::INFINITY,
        cpu_seconds: (f64::INFINITY, f64::INFINITY),
        ..Default::default()
    };
    for _ in 0..repeats.max(1) {
        for (k, c) in [&without, &with].into_iter().enumerate() {
            let mut sim = Simulation::build(c)?.simulation;
            let start = Instant::now();
            let cpu0 = cpu_seconds().unwrap_or(f64::NAN);
            for _ in 0..steps {
                sim.advance()?;
            }
            let secs = start.elapsed().as_secs_f64();
            let cpu = cpu_seconds().unwrap_or(f64::NAN) - cpu0;
            let nnz = sim.factor_nnz();
            let tm = sim.timings();
            if std::env::var_os("PENDULUM_DEBUG").is_some() {
                eprintln!(
                    "  {}: assembly {:.3} s, factorisation {:.3} s, solve {:.3} s, line search {:.3} s, residual {:.3} s",
                    if k == 0 { "without" } else { "with" },
                    tm.assembly,
                    tm.factorization,
                    tm.solve,
                    tm.line_search,
                    tm.residual
                );
            }
            if k == 0 {
                out.cpu_seconds.0 = out.cpu_seconds.0.min(cpu);
                out.seconds_without = out.seconds_without.min(secs);
                out.iterations.0 = sim.total_iterations;
                out.factor_nnz.0 = nnz;
            } else {
                out.cpu_seconds.1 = out.cpu_seconds.1.min(cpu);
                out.seconds_with = out.seconds_with.min(secs);
                out.iterations.1 = sim.total_iterations;
                out.factor_nnz.1 = nnz;
            }
        }
    }
    println!(
        "{steps} steps: without torque {:.3} s ({} Newton iterations, {:.2} ms each, factor nnz {}); \
         with {amplitude} N m {:.3} s ({} iterations, {:.2} ms each, factor nnz {}): overhead per step {:+.1} %, \
         per iteration {:+.1} %",
        out.seconds_without,
        out.iterations.0,
        1e3 * out.seconds_without / out.iterations.0.max(1) as f64,
        out.factor_nnz.0,
        out.seconds_with,
        out.iterations.1,
        1e3 * out.seconds_with / out.iterations.1.max(1) as f64,
        out.factor_nnz.1,
        100.0 * out.overhead(),
        100.0
            * ((out.seconds_with / out.iterations.1.max(1) as f64)
                / (out.seconds_without / out.iterations.0.max(1) as f64)
                - 1.0)
    );
    println!(
        "  CPU time: without {:.2} s, with {:.2} s: {:+.1} %",
        out.cpu_seconds.0,
        out.cpu_seconds.1,
        100.0 * (out.cpu_seconds.1 / out.cpu_seconds.0 - 1.0)
    );
    Ok(out)
}

/// Times `n` elastic modes (plus the rigid one) of the pendulum of `cfg` ([`crate::modal`]), best
/// of `repeats`: the stiffness at rest, then the eigensolver (factorisation, Lanczos, checks).
/// Prints the figures and returns the best total \[s\].
pub fn bench_modes(cfg: &Config, n: usize, repeats: usize) -> Result<f64, Error> {
    use crate::modal;
    let (cfg, _) = crate::commands::modes::pendulum_alone(cfg);
    let model = crate::Model::new(&cfg, mesh::generate(&cfg)?)?;
    let constraints = model.hinge.dense_rows(model.pattern.n).to_vec();
    let shift = modal::rest_shift(&model);
    println!(
        "modes: {n} elastic modes and the rigid one, {} unknowns",
        model.pattern.n
    );
    let mut best = (f64::INFINITY, 0.0, 0.0);
    for i in 0..repeats.max(1) {
        let start = Instant::now();
        let k = modal::stiffness_at_rest(&model);
        let assembled = start.elapsed().as_secs_f64();
        let modes = modal::constrained_modes(&model.pattern, &k, &model.mass, &constraints, n + 1, shift)?;
        let total = start.elapsed().as_secs_f64();
        println!(
            "  run {}: {:.4} s (stiffness {:.4} s, eigensolver {:.4} s); f1 = {:.3} Hz, f{n} = {:.3} Hz",
            i + 1,
            total,
            assembled,
            total - assembled,
            modes.frequencies_hz()[1],
            modes.frequencies_hz()[n]
        );
        if total < best.0 {
            best = (total, assembled, total - assembled);
        }
    }
    println!(
        "  best of {}: {:.4} s for {n} modes (stiffness {:.4} s, eigensolver {:.4} s)",
        repeats.max(1),
        best.0,
        best.1,
        best.2
    );
    Ok(best.0)
}

/// The real-time factors of [`bench_fmu`]: simulated time over wall time, best of the repeats.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FmuBench {
    /// At communication steps of 10 ms.
    pub factor_10ms: f64,
    /// At communication steps of 1 ms.
    pub factor_1ms: f64,
}

/// The fmpy driver that [`bench_fmu`] runs (relative to the repository's root).
pub const FMPY_SPEED: &str = "crates/fmu/examples/fmpy_speed.py";

/// `bench fmu`: the FMU through fmpy at communication steps of 10 ms and 1 ms, `seconds` simulated
/// each, best of `repeats` ([`FMPY_SPEED`], run from the repository's root). Without `fmu` the FMU
/// is built by `cargo xtask fmu` (into `$CARGO_TARGET_DIR/fmu`, else `target/fmu`); without
/// `python` the interpreter is the one `scripts/test-env` prints (with fmpy; made on first use).
/// The FMU runs with its own defaults (the default pendulum, the torque input declared): the
/// configuration's `--set` values do not reach it. Prints the driver's lines and the two
/// real-time factors, and returns them.
/// With `reduced` the FMU runs its reduced body (`model_kind = 1`).
pub fn bench_fmu(
    python: Option<&Path>,
    fmu: Option<&Path>,
    seconds: f64,
    repeats: usize,
    reduced: bool,
) -> Result<FmuBench, Error> {
    let run = |program: &Path, args: &[&std::ffi::OsStr]| -> Result<String, Error> {
        let out = std::process::Command::new(program)
            .args(args)
            .stderr(std::process::Stdio::inherit())
            .output()
            .map_err(|e| Error::io(program, e))?;
        if !out.status.success() {
            return Err(Error::Input(format!(
                "bench fmu: {} {} failed ({})",
                program.display(),
                args.iter().map(|a| a.to_string_lossy()).collect::<Vec<_>>().join(" "),
                out.status
            )));
        }
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    };
    let fmu = match fmu {
        Some(path) => path.to_path_buf(),
        None => {
            let cargo = std::env::var_os("CARGO").map_or_else(|| PathBuf::from("cargo"), PathBuf::from);
            run(&cargo, &["xtask".as_ref(), "fmu".as_ref()])?;
            let target = std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| PathBuf::from("target"), PathBuf::from);
            target.join("fmu").join("PendulumFem.fmu")
        }
    };
    if !fmu.is_file() {
        return Err(Error::Input(format!("bench fmu: no FMU at {}", fmu.display())));
    }
    let python = match python {
        Some(path) => path.to_path_buf(),
        None => PathBuf::from(run(Path::new("scripts/test-env"), &[])?.trim()),
    };
    let (seconds, repeats) = (seconds.to_string(), repeats.max(1).to_string());
    let kind = if reduced { "1" } else { "0" };
    let report = run(
        &python,
        &[
            FMPY_SPEED.as_ref(),
            fmu.as_os_str(),
            seconds.as_ref(),
            repeats.as_ref(),
            kind.as_ref(),
        ],
    )?;
    print!("{report}");
    // "FMU via fmpy h = 0.01 s: … (real-time factor 5.00, …"
    let factor = |h: &str| -> Result<f64, Error> {
        report
            .lines()
            .find(|l| l.contains(&format!("h = {h} s:")))
            .and_then(|l| l.split("real-time factor ").nth(1))
            .and_then(|rest| rest.split([',', ')']).next())
            .and_then(|x| x.trim().parse().ok())
            .ok_or_else(|| {
                Error::Input(format!(
                    "bench fmu: no real-time factor at h = {h} s in {FMPY_SPEED}'s report"
                ))
            })
    };
    let out = FmuBench {
        factor_10ms: factor("0.01")?,
        factor_1ms: factor("0.001")?,
    };
    println!(
        "FMU through fmpy, real-time factor at communication steps of 10 ms / 1 ms: {:.2} / {:.2}",
        out.factor_10ms, out.factor_1ms
    );
    Ok(out)
}
