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
//! Each figure is the best of `repeats`.

use std::time::{Duration, Instant};

use super::{temp_dir, time_default_run};
use crate::config::ModelKind;
use crate::simulation::Simulation;
use crate::{mesh, Config, Error};

/// The figures of [`bench_reduced`] \[s\].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReducedBench {
    /// A bare step at dt = 1 ms: full model, reduced body.
    pub step: [f64; 2],
    /// The default job with outputs off: full, reduced with the set-up computed, reduced with the
    /// set-up read from the disk cache.
    pub job: [f64; 3],
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
    let mesh = mesh::generate(cfg)?;
    let mut out = ReducedBench::default();
    for (k, c) in kinds.iter().enumerate() {
        let mut sim = Simulation::from_config(c, mesh.clone())?;
        out.step[k] = best(repeats, || {
            let t = Instant::now();
            for _ in 0..STEPS[k] {
                sim.step(1e-3)?;
            }
            Ok(t.elapsed())
        })? / STEPS[k] as f64;
    }
    let job = |c: &Config| time_default_run(c).map(|s| Duration::from_secs_f64(s.seconds_total));
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
    println!(
        "  default job, outputs off full {:>9.3} s    reduced {:>7.3} s (set-up computed; ratio {:.1}), {:.3} s (set-up from the disk cache; ratio {:.1})",
        out.job[0],
        out.job[1],
        out.job[0] / out.job[1],
        out.job[2],
        out.job[0] / out.job[2]
    );
    Ok(out)
}
