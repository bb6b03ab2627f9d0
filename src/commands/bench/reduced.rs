//! `bench reduced`: the reduced body (`model.kind = "reduced"`) against the full model, side by
//! side in one process on the configured pendulum:
//!
//! * the bare stepper at dt = 1 ms (`Simulation::step` alone, no record, no output): time per step
//!   and the real-time factor `dt / time per step`;
//! * the default job through the run driver with every output off (mesh, set-up, steps,
//!   `results.csv`): the full model, the reduced body with its set-up computed (an empty disk
//!   cache, as a first run), and with the set-up read from the disk cache (every later run, a
//!   sweep's cases after the first, a second FMU instance).
//!
//! Each figure is the best of `repeats`. Then the same three jobs as a user runs them:
//! `pendulum-fem run -q` in a process of its own, started from here and timed from the start to the
//! exit (the process's start, its thread pool, the first touch of its memory and the files
//! included), the disk cache empty for each computed set-up and filled for the runs that read it;
//! the kinds alternate, and each figure is the median of `repeats`.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use super::{temp_dir, time_default_run};
use crate::config::ModelKind;
use crate::simulation::Simulation;
use crate::{Config, Error};

/// The figures of [`bench_reduced`] \[s\].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReducedBench {
    /// A bare step at dt = 1 ms: full model, reduced body.
    pub step: [f64; 2],
    /// The default job with outputs off: full, reduced with the set-up computed, reduced with the
    /// set-up read from the disk cache.
    pub job: [f64; 3],
    /// The same jobs, each a process of its own (the medians).
    pub process: [f64; 3],
}

/// `pendulum-fem run -q` of the configuration file `config` into `out`, with the disk cache in
/// `cache`, in a process of its own: its wall time from start to exit \[s\].
fn time_process(config: &Path, out: &Path, cache: &Path) -> Result<f64, Error> {
    let exe = std::env::current_exe().map_err(|e| Error::Input(format!("the running program's path: {e}")))?;
    let t = Instant::now();
    let status = Command::new(&exe)
        .args(["run", "-q", "--force", "--config"])
        .arg(config)
        .arg("--out")
        .arg(out)
        .env("PENDULUM_FEM_CACHE", cache)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .map_err(|e| Error::io(&exe, e))?;
    let seconds = t.elapsed().as_secs_f64();
    if !status.success() {
        return Err(Error::Input(format!(
            "{} run --config {} failed ({status}); run it by hand to see why",
            exe.display(),
            config.display()
        )));
    }
    Ok(seconds)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The three default jobs of the module doc, each in a process of its own, `repeats` times in turn.
fn process_jobs(kinds: &[Config; 2], repeats: usize) -> Result<[f64; 3], Error> {
    let dir = temp_dir("reduced-process")?;
    let (empty, filled, out) = (dir.join("empty-cache"), dir.join("cache"), dir.join("out"));
    let configs = [dir.join("full.toml"), dir.join("reduced.toml")];
    for (c, path) in kinds.iter().zip(&configs) {
        let text = pendulum_fem_run::files::portable_toml(c, "bench configuration")?;
        std::fs::write(path, text).map_err(|e| Error::io(path, e))?;
    }
    let result = (|| {
        // the cache the later runs read
        time_process(&configs[1], &out, &filled)?;
        let mut times: [Vec<f64>; 3] = Default::default();
        for _ in 0..repeats.max(1) {
            times[0].push(time_process(&configs[0], &out, &empty)?);
            let _ = std::fs::remove_dir_all(&empty);
            times[1].push(time_process(&configs[1], &out, &empty)?);
            times[2].push(time_process(&configs[1], &out, &filled)?);
        }
        Ok(times.map(median))
    })();
    let _ = std::fs::remove_dir_all(&dir);
    result
}

/// Steps of the bare stepper timed per repeat: full model, reduced body.
const STEPS: [usize; 2] = [200, 5000];

fn best(repeats: usize, mut f: impl FnMut() -> Result<Duration, Error>) -> Result<f64, Error> {
    let mut best = f64::INFINITY;
    for _ in 0..repeats.max(1) {
        best = best.min(f()?.as_secs_f64());
    }
    Ok(best)
}

/// `bench reduced` (see the module doc); prints the table and returns the figures.
pub fn bench_reduced(cfg: &Config, repeats: usize) -> Result<ReducedBench, Error> {
    let kinds = [ModelKind::Full, ModelKind::Reduced].map(|kind| {
        let mut c = cfg.clone();
        c.model.kind = kind;
        c.output.plots = false;
        c.output.animation = false;
        c.output.paraview = false;
        c.output.viewer = false;
        c
    });
    let mut out = ReducedBench::default();
    for (k, c) in kinds.iter().enumerate() {
        let mut sim = Simulation::build(c)?.simulation;
        out.step[k] = best(repeats, || {
            let t = Instant::now();
            for _ in 0..STEPS[k] {
                sim.step(1e-3)?;
            }
            Ok(t.elapsed())
        })? / STEPS[k] as f64;
    }
    // timed from outside the run: its end includes the model's drop, which waits for a cache file
    // still being written beside the steps (crate::reduced::cache::build_and_keep)
    let job = |c: &Config| {
        let t = Instant::now();
        time_default_run(c).map(|_| t.elapsed())
    };
    out.job[0] = best(repeats, || job(&kinds[0]))?;
    let empty = temp_dir("reduced-cache")?;
    out.job[1] = best(repeats, || {
        let _ = std::fs::remove_dir_all(&empty);
        crate::reduced::cache::with_folder(Some(empty.clone()), || job(&kinds[1]))
    })?;
    out.job[2] = crate::reduced::cache::with_folder(Some(empty.clone()), || {
        job(&kinds[1])?;
        best(repeats, || {
            crate::reduced::cache::with_folder(Some(empty.clone()), || job(&kinds[1]))
        })
    })?;
    let _ = std::fs::remove_dir_all(&empty);
    out.process = process_jobs(&kinds, repeats)?;
    println!(
        "reduced body against the full model ({} modes, best of {repeats}):",
        cfg.model.modes
    );
    println!(
        "  bare step, dt = 1 ms     full {:>9.1} µs   reduced {:>7.2} µs   ratio {:>6.0}   reduced real-time factor {:.0}",
        1e6 * out.step[0],
        1e6 * out.step[1],
        out.step[0] / out.step[1],
        1e-3 / out.step[1]
    );
    let jobs = |what: &str, [full, computed, cached]: [f64; 3], tail: &str| {
        println!(
            "  {what:<25}full {full:>9.3} s    reduced {computed:>7.3} s (set-up computed; ratio {:.1}), {cached:.3} s (set-up from the disk cache; ratio {:.1}){tail}",
            full / computed,
            full / cached
        );
    };
    jobs("default job, outputs off", out.job, "");
    jobs(
        "the same, each a process",
        out.process,
        &format!("; medians of {repeats}"),
    );
    Ok(out)
}
