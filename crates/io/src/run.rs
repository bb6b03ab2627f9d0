//! `pendulum-fem run`: mesh, simulate, stream `results.csv`, summarise, and leave a consistent run
//! folder however the run ends (completed, interrupted at a step boundary, or failed; see
//! [`run_with_outputs`]).

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use crate::csv::CsvWriter;
use crate::progress::{Progress, ProgressMode};
use crate::simulation::{ContactRecord, Simulation, StepRecord};
use crate::{mesh, Config, Error};
use crate::{prepare_output_dir, FrameWriters};
use pendulum_fem_core::post::{unsigned_zero, PeriodEstimator};

/// What to run and where to write. `RunOptions { config, out: Some(dir), ..Default::default() }`
/// leaves everything else at its default (no force, progress shown, no stop flag, no checkpoints).
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// The configuration (already validated).
    pub config: Config,
    /// Output folder; `None`: a fresh folder under `output.dir`.
    pub out: Option<PathBuf>,
    /// Allow writing into an existing non-empty `out`.
    pub force: bool,
    /// No progress output.
    pub quiet: bool,
    /// When set (by a Ctrl-C or SIGTERM handler), the run stops at the next step boundary and
    /// finishes its outputs with what was computed ([`RunEnd::Interrupted`]).
    pub stop: Option<Arc<AtomicBool>>,
    /// Write the latest snapshot to [`CHECKPOINT_SNAP`] in the output folder every this many steps
    /// and when the run ends (completed or interrupted), with the configuration in
    /// [`CHECKPOINT_TOML`]; `None`: no checkpoints.
    pub checkpoint_every: Option<usize>,
    /// Continue the run in `out` from its [`CHECKPOINT_SNAP`] (see [`run`]).
    pub restart: bool,
}

/// The latest snapshot of a run with checkpoints ([`pendulum_fem_core::Snapshot::to_bytes`]).
pub const CHECKPOINT_SNAP: &str = "checkpoint.snap";
/// The configuration of a run with checkpoints, read by `run --restart`.
pub const CHECKPOINT_TOML: &str = "checkpoint.toml";

/// Figures of a finished run.
#[derive(Clone, Debug, Default)]
pub struct RunSummary {
    /// Output folder.
    pub out_dir: PathBuf,
    /// Files written.
    pub files: Vec<PathBuf>,
    /// Triangles and nodes of the mesh, unknowns of the system.
    pub mesh_triangles: usize,
    /// Mesh nodes.
    pub mesh_nodes: usize,
    /// Unknowns (displacements + 2 multipliers).
    pub unknowns: usize,
    /// How the run ended.
    pub end: RunEnd,
    /// Steps computed.
    pub steps: usize,
    /// Time of the last state computed \[s\].
    pub time_reached: f64,
    /// The length of a shortened last step that lands on `time.end` \[s\], when `time.end` is
    /// not a multiple of `time.dt` (see [`StepPlan`]).
    pub last_step: Option<f64>,
    /// Newton iterations (linear solves) over all steps.
    pub newton_iterations: usize,
    /// Numeric factorisations over the run.
    pub factorizations: usize,
    /// Step cut-backs.
    pub cutbacks: usize,
    /// Final proxy angle \[rad\].
    pub theta_final: f64,
    /// Smallest and largest proxy angle \[rad\].
    pub theta_range: (f64, f64),
    /// Period from zero crossings \[s\]; `None` when the head struck a wall (see
    /// [`RunSummary::impacts`]).
    pub period: Option<f64>,
    /// Largest von Mises stress over the run \[Pa\].
    pub von_mises_max: f64,
    /// With a wall: the impacts and the largest contact force over the records \[N\].
    pub contact: Option<(usize, f64)>,
    /// With a wall: count, interval, restitution and rebound of the impacts (what the summary
    /// reports instead of [`RunSummary::period`], which zero crossings inside the impacts spoil).
    pub impacts: Option<crate::impacts::ImpactSummary>,
    /// Largest energy error over the run, `max |E(t) − E(0) − W(t)| / energy_scale` (see
    /// [`EnergyAudit`]).
    pub energy_error: f64,
    /// The energy scale of the run \[J\] (see [`EnergyAudit`]).
    pub energy_scale: f64,
    /// Wall time: meshing \[s\].
    pub seconds_mesh: f64,
    /// Wall time: set-up (operators, symbolic factorisation) \[s\].
    pub seconds_setup: f64,
    /// Wall time: time stepping including post-processing and writing \[s\].
    pub seconds_steps: f64,
    /// Wall time in total \[s\].
    pub seconds_total: f64,
    /// Wall time spent building frames and writing ParaView files, animations, plots and the
    /// viewer (included in `seconds_steps` and `seconds_total`) \[s\].
    pub seconds_outputs: f64,
    /// Solver timings.
    pub timings: pendulum_fem_core::newton::Timings,
}

/// The values of a record in CSV column order, a negative zero as `0`
/// ([`pendulum_fem_core::post::unsigned_zero`]).
/// The columns are [`StepRecord::HEADER`]'s, then [`StepRecord::CONTACT_HEADER`]'s for a model
/// with a wall.
pub fn csv_values(r: &StepRecord) -> Vec<f64> {
    let mut v = vec![
        r.time,
        r.theta,
        r.omega,
        r.alpha,
        r.kinetic,
        r.strain,
        r.gravity,
        r.total,
        r.hinge_force[0],
        r.hinge_force[1],
        r.von_mises_max,
        r.newton_iterations as f64,
        r.torque,
        r.torque_work,
        r.angular_momentum,
    ];
    if let Some(c) = &r.contact {
        v.extend([c.gap, c.force, c.energy, c.impacts as f64]);
    }
    v.into_iter().map(unsigned_zero).collect()
}

/// The main job: prepares the output folder (before computing anything), then runs with every
/// output the configuration asks for.
///
/// **Restart** (`opts.restart`, the folder in `opts.out`): the run continues from the folder's
/// [`CHECKPOINT_SNAP`] (made with the same configuration and mesh; `time.end` may be larger). The
/// rows of `results.csv` after the checkpoint's step are dropped (they are computed again; the
/// checkpoint's own row must equal the restored state's, bit for bit), the ParaView frames up to it
/// stay in `pendulum.pvd`, and both are appended to, so that `results.csv` is byte for byte that
/// of an uninterrupted run with the same steps. The animations and the viewer show the frames from
/// the checkpoint on; the plots are drawn from the whole `results.csv`. A run finished on a
/// shortened last step (`time.end` off the `time.dt` grid) continues from there with steps of
/// `time.dt`, which an uninterrupted run would not have taken.
pub fn run(opts: &RunOptions) -> Result<RunSummary, Error> {
    let out_dir = if opts.restart {
        let dir = opts
            .out
            .clone()
            .ok_or_else(|| Error::Input("run --restart: name the folder of the run to continue".into()))?;
        let snap = dir.join(CHECKPOINT_SNAP);
        if !snap.is_file() {
            return Err(Error::Input(format!(
                "run --restart {}: no {CHECKPOINT_SNAP} there (a run writes it with --checkpoint-every N)",
                dir.display()
            )));
        }
        // refuse another model before anything in the folder is touched
        let bytes = std::fs::read(&snap).map_err(|e| Error::io(&snap, e))?;
        let snapshot = pendulum_fem_core::Snapshot::from_bytes(&bytes, &snap.display().to_string())?;
        // the model's own fingerprint (with its torque table and, with a deformable wall, the block)
        let model = crate::simulation::Model::new(&opts.config, mesh::generate(&opts.config)?)?;
        if let Some(parts) = snapshot.fingerprint().differences(&model.fingerprint, &opts.config) {
            return Err(Error::Input(format!(
                "{}: made for another model: {parts} (fingerprint {}; this configuration gives {}): restart with \
                 the configuration of the run (only time.end and [output] may change)",
                snap.display(),
                snapshot.fingerprint(),
                model.fingerprint
            )));
        }
        dir
    } else {
        prepare_output_dir(&opts.config.output.dir, opts.out.as_deref(), opts.force)?
    };
    run_with_outputs(opts, out_dir, true, |_, _| Ok(()))
}

/// Writes the snapshot of `sim` to `dir/checkpoint.snap` atomically (a temporary file, then a
/// rename: a run killed meanwhile leaves the previous checkpoint intact).
fn write_checkpoint(dir: &std::path::Path, sim: &Simulation) -> Result<(), Error> {
    let path = dir.join(CHECKPOINT_SNAP);
    let bytes = sim.snapshot().to_bytes();
    crate::vtu::write_atomically(&path, |w| w.write_all(&bytes))
}

/// Writes the configuration of a run with checkpoints to `dir/checkpoint.toml` (file paths made
/// absolute, so that it reads back from any folder).
fn write_checkpoint_config(dir: &std::path::Path, cfg: &Config) -> Result<(), Error> {
    let mut cfg = cfg.clone();
    for file in [&mut cfg.mesh.file, &mut cfg.torque.file].into_iter().flatten() {
        if let Ok(abs) = std::path::absolute(&*file) {
            *file = abs;
        }
    }
    let text = toml::to_string(&cfg).map_err(|e| Error::Input(format!("{CHECKPOINT_TOML}: {e}")))?;
    let path = dir.join(CHECKPOINT_TOML);
    crate::vtu::write_atomically(&path, |w| w.write_all(text.as_bytes()))
}

/// The records before a restarted run's checkpoint and the `(step, time)` of every row up to and
/// including it.
type Resumed = (Vec<StepRecord>, Vec<(usize, f64)>);

/// A restarted run: the state is restored from the checkpoint, `results.csv` is cut after the
/// checkpoint's row; returns the rows before the checkpoint's (as records) and the `(step, time)`
/// of every row up to and including it.
fn resume(dir: &std::path::Path, sim: &mut Simulation) -> Result<Resumed, Error> {
    let snap_path = dir.join(CHECKPOINT_SNAP);
    let bytes = std::fs::read(&snap_path).map_err(|e| Error::io(&snap_path, e))?;
    let snap = pendulum_fem_core::Snapshot::from_bytes(&bytes, &snap_path.display().to_string())?;
    sim.restore(&snap)
        .map_err(|e| Error::Input(format!("{}: {e}", snap_path.display())))?;
    let k = snap.step();
    let csv_path = dir.join("results.csv");
    let text = std::fs::read_to_string(&csv_path).map_err(|e| Error::io(&csv_path, e))?;
    // the header and the rows of steps 0..=k, each ending in a newline
    let mut end = 0;
    for line in 0..k + 2 {
        match text[end..].find('\n') {
            Some(i) => end += i + 1,
            None => {
                return Err(Error::Input(format!(
                    "{}: {} complete rows, but the checkpoint is at step {k}: the file does not belong to it",
                    csv_path.display(),
                    line.saturating_sub(1)
                )))
            }
        }
    }
    let columns = csv_values(&sim.record(0)).len();
    let mut rows = Vec::with_capacity(k + 1);
    for (i, line) in text[..end].lines().skip(1).enumerate() {
        let values: Result<Vec<f64>, _> = line.split(',').map(str::parse::<f64>).collect();
        match values {
            Ok(v) if v.len() == columns => rows.push(record_of_row(i, &v)),
            _ => {
                return Err(Error::Input(format!(
                    "{}:{}: not a row of {columns} numbers",
                    csv_path.display(),
                    i + 2
                )))
            }
        }
    }
    let its = sim.last_newton_iterations();
    let now = csv_values(&sim.record(its));
    let row_k = csv_values(&rows[k]);
    if now.iter().zip(&row_k).any(|(a, b)| a.to_bits() != b.to_bits()) {
        return Err(Error::Input(format!(
            "{}: the row of step {k} differs from the state of {}: they are not of the same run",
            csv_path.display(),
            snap_path.display()
        )));
    }
    let file = std::fs::OpenOptions::new()
        .write(true)
        .open(&csv_path)
        .map_err(|e| Error::io(&csv_path, e))?;
    file.set_len(end as u64).map_err(|e| Error::io(&csv_path, e))?;
    let times = rows.iter().map(|r| (r.step, r.time)).collect();
    rows.truncate(k);
    Ok((rows, times))
}

/// Cuts the rows of a CSV file (a header line, then rows whose first column is the time) after
/// time `t`, for a restarted run: the rows after its checkpoint are computed again.
fn cut_rows_after(path: &std::path::Path, t: f64) -> Result<(), Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let mut kept = String::new();
    for (i, line) in text.lines().enumerate() {
        let time = line.split(',').next().and_then(|c| c.parse::<f64>().ok());
        if i == 0 || time.is_some_and(|time| time <= t) {
            kept.push_str(line);
            kept.push('\n');
        }
    }
    crate::vtu::write_atomically(path, |w| w.write_all(kept.as_bytes()))
}

/// Header of `events.csv`.
pub const EVENTS_HEADER: &str = "time_s,event,theta_rad,omega_rad_s,impulse_N_s,max_penetration_m,max_force_N";

/// Writes `events.csv` (every contact event so far; replaced atomically, so that a stopped or
/// restarted run leaves it whole).
fn write_events(dir: &std::path::Path, events: &[pendulum_fem_core::simulation::ContactEvent]) -> Result<(), Error> {
    let mut text = format!("{EVENTS_HEADER}\n");
    for e in events {
        let [time, theta, omega, impulse, penetration, force] =
            [e.time, e.theta, e.omega, e.impulse, e.penetration, e.force].map(unsigned_zero);
        text.push_str(&format!(
            "{time},{},{theta},{omega},{impulse},{penetration},{force}\n",
            e.kind.name()
        ));
    }
    crate::vtu::write_atomically(&dir.join("events.csv"), |w| w.write_all(text.as_bytes()))
}

/// The record of a `results.csv` row (in [`csv_values`] order) of step `step`.
fn record_of_row(step: usize, v: &[f64]) -> StepRecord {
    StepRecord {
        step,
        time: v[0],
        theta: v[1],
        omega: v[2],
        alpha: v[3],
        kinetic: v[4],
        strain: v[5],
        gravity: v[6],
        total: v[7],
        hinge_force: [v[8], v[9]],
        von_mises_max: v[10],
        newton_iterations: v[11] as usize,
        torque: v[12],
        torque_work: v[13],
        angular_momentum: v[14],
        contact: (v.len() >= 19).then(|| ContactRecord {
            gap: v[15],
            force: v[16],
            energy: v[17],
            impacts: v[18] as usize,
        }),
    }
}

/// Runs the simulation described by `opts` writing only `results.csv`, calling `observe` after
/// every record (step 0 included) with the simulation and the record.
pub fn run_with(
    opts: &RunOptions,
    out_dir: PathBuf,
    observe: impl FnMut(&Simulation, &StepRecord) -> Result<(), Error>,
) -> Result<RunSummary, Error> {
    run_with_outputs(opts, out_dir, false, observe)
}

/// The steps of a run: `full` steps of `time.dt`, then, when `time.end` is not a multiple of
/// `time.dt` (to 1e-9 relative), one shorter `last` step that lands exactly on `time.end`.
/// `time.end = 0.015` with `dt = 0.01`: one step to 0.01, one of 0.005 to 0.015.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepPlan {
    /// Steps of `time.dt`.
    pub full: usize,
    /// Length of the shortened last step \[s\], if any.
    pub last: Option<f64>,
}

impl StepPlan {
    /// The plan of a time section.
    pub fn of(time: &crate::config::Time) -> Self {
        let x = time.end / time.dt;
        let n = x.round();
        if (x - n).abs() <= 1e-9 * x.max(1.0) {
            Self {
                full: n as usize,
                last: None,
            }
        } else {
            let full = x.floor();
            Self {
                full: full as usize,
                last: Some(time.end - full * time.dt),
            }
        }
    }

    /// Steps in all.
    pub fn steps(&self) -> usize {
        self.full + usize::from(self.last.is_some())
    }
}

/// How a run ended.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RunEnd {
    /// Reached `time.end`.
    #[default]
    Completed,
    /// Stopped at a step boundary because [`RunOptions::stop`] was set (Ctrl-C, SIGTERM).
    Interrupted,
}

/// Runs the simulation into `out_dir`; with `frames` also the ParaView files, animations, plots
/// and the viewer (as `output.*` selects).
///
/// Whatever happens, the folder stays consistent: `status.json` says `"running"` from the start
/// and `"ok"`, `"interrupted"` or `"failed"` (with the error) at the end, with the last step and
/// time reached. When a step fails or the run is interrupted, `results.csv` is complete up to the
/// last step computed, that step is written as the last frame, and the plots, animations and
/// viewer show what was computed; a failure is then returned as the error.
pub fn run_with_outputs(
    opts: &RunOptions,
    out_dir: PathBuf,
    frames: bool,
    observe: impl FnMut(&Simulation, &StepRecord) -> Result<(), Error>,
) -> Result<RunSummary, Error> {
    let status_path = out_dir.join(crate::status::STATUS_JSON);
    let end_time = opts.config.time.end;
    crate::status::RunStatus::running(end_time).write(&status_path)?;
    let mut reached = None;
    let result = run_steps(opts, out_dir, frames, observe, &mut reached);
    let status = match &result {
        Ok(s) if s.end == RunEnd::Interrupted => crate::status::RunStatus::interrupted(end_time, reached),
        Ok(_) => crate::status::RunStatus::ok(end_time, reached),
        Err(e) => crate::status::RunStatus::failed(end_time, reached, e),
    };
    // A run that failed reports its own error, not a failure to write the status.
    let written = status.write(&status_path);
    let mut summary = result?;
    written?;
    summary.files.push(status_path);
    Ok(summary)
}

/// The run proper; `reached` follows the last step written to `results.csv` (step, time).
fn run_steps(
    opts: &RunOptions,
    out_dir: PathBuf,
    frames: bool,
    mut observe: impl FnMut(&Simulation, &StepRecord) -> Result<(), Error>,
    reached: &mut Option<(usize, f64)>,
) -> Result<RunSummary, Error> {
    let start = Instant::now();
    let cfg = &opts.config;
    let mesh = mesh::generate(cfg)?;
    if let Some(warning) = mesh::max_size_warning(cfg, &mesh) {
        eprintln!("{warning}");
    }
    let seconds_mesh = start.elapsed().as_secs_f64();
    let t_setup = Instant::now();
    let mut sim = Simulation::from_config(cfg, mesh)?;
    let seconds_setup = t_setup.elapsed().as_secs_f64();
    let t_steps = Instant::now();
    let csv_path = out_dir.join("results.csv");
    let header = StepRecord::header(sim.model.wall.is_some());
    let (earlier, earlier_times) = match opts.restart {
        true => resume(&out_dir, &mut sim)?,
        false => Default::default(),
    };
    if opts.checkpoint_every.is_some() {
        write_checkpoint_config(&out_dir, cfg)?;
    }
    let mut csv = match opts.restart {
        true => CsvWriter::append(&csv_path, &header)?,
        false => CsvWriter::create(&csv_path, &header)?,
    };
    // with a wall, the sub-steps inside impacts go to impacts.csv (the columns of results.csv)
    let mut impacts_csv = match sim.model.wall.is_some() {
        true => {
            sim.record_impacts(true);
            let path = out_dir.join(crate::writers::names::IMPACTS_CSV);
            Some(match opts.restart && path.is_file() {
                true => {
                    cut_rows_after(&path, sim.state.t)?;
                    CsvWriter::append(&path, &header)?
                }
                false => CsvWriter::create(&path, &header)?,
            })
        }
        false => None,
    };
    let mut summary = RunSummary {
        out_dir: out_dir.clone(),
        mesh_triangles: sim.model.mesh.triangles.len(),
        mesh_nodes: sim.model.mesh.num_nodes(),
        unknowns: 2 * sim.model.mesh.num_nodes() + 2,
        theta_range: (f64::INFINITY, f64::NEG_INFINITY),
        ..Default::default()
    };
    let o = &cfg.output;
    let wants_frames = frames && (o.paraview || o.animation || o.viewer);
    if frames && o.paraview {
        if let Some(warning) = output_size_warning(cfg, &sim.model.mesh) {
            eprintln!("{warning}");
        }
    }
    // the wall (when there is one) is drawn in the pictures and is a block of the ParaView output
    let wall = crate::writers::WallOutput::of(cfg, &sim.model.mesh);
    let wall_x = wall.as_ref().filter(|w| w.rigid).map(|w| w.face_x);
    // a second body (a deformable wall) is drawn displaced, not turned with the pendulum
    let pendulum_nodes = sim.model.bodies[0].nodes.end;
    let with_wall = |w: FrameWriters| match &wall {
        Some(wall) => w.with_pendulum_nodes(pendulum_nodes).with_wall(wall.clone()),
        None => Ok(w.with_pendulum_nodes(pendulum_nodes)),
    };
    let mut writers = match (frames, opts.restart) {
        (true, false) => Some(FrameWriter::start(with_wall(FrameWriters::new(
            &out_dir,
            &sim.model.mesh,
            o,
            wall_x,
        )?)?)),
        (true, true) => Some(FrameWriter::start(with_wall(FrameWriters::resume(
            &out_dir,
            &sim.model.mesh,
            o,
            wall_x,
            &earlier_times,
        )?)?)),
        (false, _) => None,
    };
    let mode = if opts.quiet {
        ProgressMode::Quiet
    } else {
        ProgressMode::detect(false)
    };
    let mut progress = Progress::new(StepPlan::of(&cfg.time).steps(), mode);
    let mut seconds_outputs = 0.0;
    let mut period = PeriodEstimator::default();
    let mut impacts = crate::impacts::ImpactSummary::default();
    let mut audit = EnergyAudit::of(&sim.model);
    let plan = StepPlan::of(&cfg.time);
    summary.last_step = plan.last;
    let stop_requested = || opts.stop.as_ref().is_some_and(|s| s.load(Ordering::SeqCst));
    for r in &earlier {
        period.push(r.time, r.theta);
        summary.theta_range.0 = summary.theta_range.0.min(r.theta);
        summary.theta_range.1 = summary.theta_range.1.max(r.theta);
        summary.von_mises_max = summary.von_mises_max.max(r.von_mises_max);
        audit.push(r);
    }
    let mut record = sim.record(sim.last_newton_iterations());
    // a restarted run's first record (the checkpoint's) is in results.csv and the frames already
    let mut resumed = opts.restart;
    // The loop ends with `Ok(())` (completed or interrupted) or the error that stopped it; the
    // outputs of what was computed are finished either way.
    let mut events_written = usize::MAX;
    let stopped: Result<(), Error> = loop {
        if !resumed {
            if let Err(e) = csv.row(&csv_values(&record)) {
                break Err(e);
            }
        }
        if sim.model.wall.is_some() && sim.contact_events().len() != events_written {
            events_written = sim.contact_events().len();
            if let Err(e) = write_events(&out_dir, sim.contact_events()) {
                break Err(e);
            }
        }
        *reached = Some((record.step, record.time));
        if let Some(w) = writers.as_mut() {
            if wants_frames && w.wants(record.step) && !resumed {
                let t_out = Instant::now();
                if let Err(e) = w.send(sim.frame_data(record.theta), false) {
                    break Err(e);
                }
                seconds_outputs += t_out.elapsed().as_secs_f64();
            }
        }
        if let Err(e) = observe(&sim, &record) {
            break Err(e);
        }
        progress.update(record.step, record.time, sim.total_iterations);
        period.push(record.time, record.theta);
        summary.theta_range.0 = summary.theta_range.0.min(record.theta);
        summary.theta_range.1 = summary.theta_range.1.max(record.theta);
        summary.von_mises_max = summary.von_mises_max.max(record.von_mises_max);
        summary.theta_final = record.theta;
        if sim.model.wall.is_some() {
            impacts.observe(sim.contact_events(), record.theta);
        }
        if let Some(c) = record.contact {
            // the peaks between the records are in the events
            let peaks = sim.contact_events().iter().map(|e| e.force).fold(0.0, f64::max);
            let largest = summary.contact.map_or(0.0, |(_, f)| f);
            summary.contact = Some((c.impacts, largest.max(c.force).max(peaks)));
        }
        let error = audit.push(&record);
        if cfg.output.energy_watchdog > 0.0 && error > cfg.output.energy_watchdog {
            break Err(audit.divergence(&record, cfg.output.energy_watchdog));
        }
        if let Some(every) = opts.checkpoint_every {
            if sim.step.is_multiple_of(every.max(1)) && !resumed {
                // every row and frame up to this step on disk first, then the snapshot
                let written = csv.flush().and_then(|()| writers.as_mut().map_or(Ok(()), |w| w.sync()));
                if let Err(e) = written.and_then(|()| write_checkpoint(&out_dir, &sim)) {
                    break Err(e);
                }
            }
        }
        resumed = false;
        if sim.step >= plan.steps() {
            break Ok(());
        }
        if stop_requested() {
            summary.end = RunEnd::Interrupted;
            break Ok(());
        }
        // the stepper advances; the record (with the nodal stresses) is this loop's observation
        let stepped = if sim.step < plan.full {
            sim.step(cfg.time.dt)
        } else {
            sim.step_to(cfg.time.end)
        };
        match stepped {
            Ok(its) => record = sim.record(its),
            Err(e) => break Err(e),
        }
        if let Some(w) = impacts_csv.as_mut() {
            if let Err(e) = sim.take_impact_records().iter().try_for_each(|r| w.row(&csv_values(r))) {
                break Err(e);
            }
        }
    };
    progress.finish();
    // Finish every output with what was computed; the first error wins.
    let mut first_error = stopped.err();
    if let (true, Some(w)) = (wants_frames, writers.as_mut()) {
        let t_out = Instant::now();
        if let Err(e) = w.send(sim.frame_data(record.theta), true) {
            first_error.get_or_insert(e);
        }
        seconds_outputs += t_out.elapsed().as_secs_f64();
    }
    if sim.model.wall.is_some() {
        summary.files.push(out_dir.join("events.csv"));
    }
    if let Some(w) = impacts_csv {
        match w.finish() {
            Ok(path) => summary.files.push(path),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    match csv.finish() {
        Ok(path) => summary.files.push(path),
        Err(e) => {
            first_error.get_or_insert(e);
        }
    }
    // the end of a completed or interrupted run is a checkpoint too (a finished run can be continued)
    if let (None, Some(_)) = (&first_error, opts.checkpoint_every) {
        match write_checkpoint(&out_dir, &sim) {
            Ok(()) => summary.files.push(out_dir.join(CHECKPOINT_SNAP)),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    if let Some(w) = writers {
        let t_out = Instant::now();
        match w.finish() {
            Ok(paths) => summary.files.extend(paths),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
        seconds_outputs += t_out.elapsed().as_secs_f64();
    }
    if let Some(e) = first_error {
        return Err(e);
    }
    summary.seconds_outputs = seconds_outputs;
    summary.steps = sim.step;
    summary.time_reached = sim.state.t;
    summary.newton_iterations = sim.total_iterations;
    summary.factorizations = sim.total_factorizations;
    summary.cutbacks = sim.cutbacks;
    if sim.model.wall.is_some() {
        impacts.of_events(sim.contact_events());
        summary.impacts = Some(impacts);
    }
    // a head that struck the wall crosses θ = 0 only inside the impacts: no period (the summary
    // reports the impacts, a sweep's summary.csv leaves `period_s` empty)
    summary.period = period.period().filter(|_| summary.impacts.is_none_or(|i| i.count == 0));
    summary.energy_error = audit.error();
    summary.energy_scale = audit.scale();
    summary.timings = sim.timings();
    summary.seconds_mesh = seconds_mesh;
    summary.seconds_setup = seconds_setup;
    summary.seconds_steps = t_steps.elapsed().as_secs_f64();
    summary.seconds_total = start.elapsed().as_secs_f64();
    Ok(summary)
}

/// The energy balance of a run, fed one [`StepRecord`] at a time.
///
/// The **energy error** at step n is `|ΔE − W| / scale`, with `ΔE = E_total(tₙ) − E_total(0)` and
/// `W` the work of the torque up to tₙ (`torque_work_J`): without external work the total energy is
/// conserved, so whatever remains is the integrator's (or a divergence's) doing. The **energy
/// scale** is the energy the run has available: the initial kinetic energy, plus the weight times
/// the largest change of the centroid's height that the swing allows ([`Model::potential_range`]),
/// plus the largest |W| so far; never below the floor `10⁻³ m g₀ L` ([`Model::energy_floor`]), for
/// a body that has nothing to move it. The scale is known from the first step on (only the torque's work can raise it), so
/// the watchdog judges the first steps of a swing by what the swing has available, not by the
/// little kinetic energy it has gained so far (the tutorial's zero start loses 1.2e-4 J in its
/// first step, 3e-5 of its available 3.75 J).
///
/// [`Model::potential_range`]: crate::simulation::Model::potential_range
/// [`Model::energy_floor`]: crate::simulation::Model::energy_floor
#[derive(Clone, Debug)]
pub struct EnergyAudit {
    first: Option<StepRecord>,
    floor: f64,
    /// Weight times the centroid's possible height change \[J\].
    potential: f64,
    scale: f64,
    /// Largest `|W|` \[J\].
    largest_work: f64,
    /// Largest `|ΔE − W|` \[J\].
    largest_defect: f64,
}

impl EnergyAudit {
    /// An audit with the given floor of the energy scale and the weight times the centroid's
    /// possible height change ([`crate::simulation::Model::potential_range`]) \[J\].
    pub fn new(floor: f64, potential: f64) -> Self {
        Self {
            first: None,
            floor,
            potential,
            scale: floor.max(potential),
            largest_work: 0.0,
            largest_defect: 0.0,
        }
    }

    /// The audit of a run of `model`.
    pub fn of(model: &crate::simulation::Model) -> Self {
        Self::new(model.energy_floor(), model.potential_range())
    }

    /// Takes the next record; returns its energy error judged with the scale so far.
    pub fn push(&mut self, r: &StepRecord) -> f64 {
        let first = self.first.get_or_insert_with(|| r.clone());
        self.largest_work = self.largest_work.max(r.torque_work.abs());
        let available = first.kinetic.abs() + self.potential + self.largest_work;
        self.scale = self.floor.max(available);
        let defect = (r.total - first.total - r.torque_work).abs();
        self.largest_defect = self.largest_defect.max(defect);
        defect / self.scale
    }

    /// The floor of the energy scale \[J\].
    pub fn floor(&self) -> f64 {
        self.floor
    }

    /// The energy scale so far \[J\].
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The largest energy error so far, with the current scale.
    pub fn error(&self) -> f64 {
        self.largest_defect / self.scale
    }

    /// The watchdog's error for `r`: time, energies and what to try.
    pub fn divergence(&self, r: &StepRecord, limit: f64) -> Error {
        let first = self.first.as_ref().unwrap_or(r);
        let defect = r.total - first.total - r.torque_work;
        Error::Divergence {
            step: r.step,
            t: r.time,
            message: format!(
                "energy error {:.3e} of the energy scale {:.4e} J exceeds output.energy_watchdog = {limit}: \
                 the total energy changed by {:.4e} J while the torque did {:.4e} J of work (now kinetic {:.4e} J, \
                 strain {:.4e} J, gravity {:.4e} J). The step is probably too large for this motion: try a smaller \
                 time.dt or time.max_rotation_deg, or time.scheme = \"hht\"; output.energy_watchdog = 0 runs on \
                 regardless",
                defect.abs() / self.scale,
                self.scale,
                r.total - first.total,
                r.torque_work,
                r.kinetic,
                r.strain,
                r.gravity
            ),
        }
    }
}

/// Estimated output above which a run warns before it starts \[bytes\].
pub const LARGE_OUTPUT_BYTES: u64 = 1_000_000_000;

/// A warning naming the estimated size of the ParaView frames when it exceeds
/// [`LARGE_OUTPUT_BYTES`], with the keys that reduce it; `None` below.
pub fn output_size_warning(cfg: &crate::Config, mesh: &crate::Mesh) -> Option<String> {
    let steps = StepPlan::of(&cfg.time).steps();
    let stride = cfg.output.paraview_stride();
    let frames = (steps / stride + 2) as u64;
    let per_frame = crate::pvd::estimated_frame_bytes(mesh);
    let total = frames * per_frame;
    (total > LARGE_OUTPUT_BYTES).then(|| {
        let suggested = (total / (LARGE_OUTPUT_BYTES / 2)).max(2) * stride as u64;
        format!(
            "warning: this run will write about {:.1} GB of ParaView frames ({frames} frames of about {:.2} MB); \
             set output.paraview_every = {suggested} (or more) or output.paraview = false to write less",
            total as f64 / 1e9,
            per_frame as f64 / 1e6
        )
    })
}

/// Frame outputs written on a thread of their own, so that serialising ParaView files and keeping
/// frames for the pictures overlaps the time stepping. The channel holds at most
/// [`FRAME_QUEUE`] frames, so memory stays bounded when the writer falls behind.
struct FrameWriter {
    /// Frames (and whether each is the run's last), or a request to confirm that every frame
    /// before it is written.
    sender: Option<std::sync::mpsc::SyncSender<FrameMessage>>,
    handle: Option<std::thread::JoinHandle<Result<FrameWriters, Error>>>,
    /// The thinning of the writers (they live on the thread).
    wants: crate::writers::Thinning,
}

/// What the run sends to the frame writer thread.
enum FrameMessage {
    /// A frame, and whether it is the run's last.
    Frame(crate::simulation::FrameData, bool),
    /// Answer on this channel once every frame before has been written.
    Sync(std::sync::mpsc::Sender<()>),
}

/// Frames waiting for the writer thread at most.
const FRAME_QUEUE: usize = 4;

impl FrameWriter {
    fn start(mut writers: FrameWriters) -> Self {
        let wants = writers.clone_thinning();
        let (sender, receiver) = std::sync::mpsc::sync_channel::<FrameMessage>(FRAME_QUEUE);
        let handle = std::thread::spawn(move || {
            for message in receiver {
                match message {
                    FrameMessage::Frame(data, true) => writers.last_frame(&data.as_frame())?,
                    FrameMessage::Frame(data, false) => writers.frame(&data.as_frame())?,
                    FrameMessage::Sync(done) => {
                        let _ = done.send(());
                    }
                }
            }
            Ok(writers)
        });
        Self {
            sender: Some(sender),
            handle: Some(handle),
            wants,
        }
    }

    /// Whether the writers take a frame of `step` (see [`FrameWriters::wants`]).
    fn wants(&self, step: usize) -> bool {
        self.wants.wants(step)
    }

    /// Queues a frame (`last`: the last state of the run); if the writer thread has stopped with an
    /// error, returns that error.
    fn send(&mut self, data: crate::simulation::FrameData, last: bool) -> Result<(), Error> {
        let sent = self
            .sender
            .as_ref()
            .map(|s| s.send(FrameMessage::Frame(data, last)).is_ok())
            .unwrap_or(false);
        if sent {
            return Ok(());
        }
        self.sender = None;
        Err(self.join_error())
    }

    /// Waits until every frame sent so far is written (before a checkpoint); if the writer
    /// thread has stopped with an error, returns that error.
    fn sync(&mut self) -> Result<(), Error> {
        let (done, wait) = std::sync::mpsc::channel();
        let confirmed = self
            .sender
            .as_ref()
            .is_some_and(|s| s.send(FrameMessage::Sync(done)).is_ok() && wait.recv().is_ok());
        if confirmed {
            return Ok(());
        }
        self.sender = None;
        Err(self.join_error())
    }

    fn join_error(&mut self) -> Error {
        match self.handle.take().map(|h| h.join()) {
            Some(Ok(Err(e))) => e,
            Some(Err(_)) => Error::Input("the frame writer thread panicked".into()),
            _ => Error::Input("the frame writer stopped unexpectedly".into()),
        }
    }

    /// Waits for the queued frames, then writes the animations, the viewer and the plots.
    fn finish(mut self) -> Result<Vec<PathBuf>, Error> {
        drop(self.sender.take());
        let handle = self.handle.take().ok_or_else(|| self.join_error())?;
        let writers = handle
            .join()
            .map_err(|_| Error::Input("the frame writer thread panicked".into()))??;
        writers.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::cut_rows_after;

    #[test]
    fn a_restart_cuts_the_impact_rows_after_its_checkpoint_and_keeps_the_header() {
        let dir = std::env::temp_dir().join(format!("pendulum-fem-cut-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("impacts.csv");
        std::fs::write(&path, "time_s,theta_rad\n0.1,1\n0.2,2\n0.25,3\n0.3,4\n").unwrap();
        cut_rows_after(&path, 0.25).unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "time_s,theta_rad\n0.1,1\n0.2,2\n0.25,3\n"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
