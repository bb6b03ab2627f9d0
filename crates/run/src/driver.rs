//! `pendulum-fem run`: mesh, simulate, stream `results.csv`, summarise, and leave a consistent run
//! folder however the run ends (completed, interrupted at a step boundary, or failed; see
//! [`run_with`]). What else watches the run (the pictures and ParaView frames, a progress bar) is a
//! [`RunObserver`], attached through [`RunOptions::observers`].

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use pendulum_fem_core::mesh;
use pendulum_fem_core::post::PeriodEstimator;
use pendulum_fem_core::simulation::{ContactEvent, Simulation, StepRecord};
use pendulum_fem_core::{Config, Error};

use crate::audit::EnergyAudit;
use crate::checkpoint::{cut_rows_after, resume, write_checkpoint, write_checkpoint_config, CHECKPOINT_SNAP};
use crate::csv::CsvWriter;
use crate::impacts::ImpactSummary;
use crate::prepare_output_dir;
use crate::rows::{csv_values, write_events};
use pendulum_fem_core::config::StepPlan;

/// What a run's observers are made from, once its simulation is set up (and, for a restart,
/// returned to its checkpoint).
pub struct RunStart<'a> {
    /// The configuration of the run.
    pub config: &'a Config,
    /// The simulation, at its first record's state.
    pub sim: &'a Simulation,
    /// The run's folder.
    pub out_dir: &'a Path,
    /// A restarted run: the `(step, time)` of every `results.csv` row up to and including the
    /// checkpoint's; empty for a fresh run.
    pub resumed: &'a [(usize, f64)],
}

/// Something that watches a run beside its CSV files: the pictures and ParaView frames
/// (`pendulum-fem-render`), the CLI's progress bar. The driver calls it in this order:
/// [`RunObserver::record`] for every record, [`RunObserver::sync`] before each checkpoint, and
/// [`RunObserver::finish`] once at the end, whether the run completed, was interrupted or failed.
pub trait RunObserver {
    /// Takes the record of the latest step (step 0's first). `resumed`: the record is a restarted
    /// run's checkpoint, whose outputs its folder already holds.
    fn record(&mut self, sim: &mut Simulation, record: &StepRecord, resumed: bool) -> Result<(), Error>;

    /// Everything observed so far is on disk (a checkpoint follows).
    fn sync(&mut self) -> Result<(), Error> {
        Ok(())
    }

    /// The run has ended at `last` (the last state computed); returns the files written.
    fn finish(self: Box<Self>, sim: &mut Simulation, last: &StepRecord) -> Result<Vec<PathBuf>, Error>;
}

/// Makes an observer for a run ([`RunOptions::observers`]); `None`: this run needs none (say,
/// pictures that the configuration switched off).
pub type MakeObserver = dyn Fn(&RunStart<'_>) -> Result<Option<Box<dyn RunObserver>>, Error> + Send + Sync;

/// An observer maker that [`RunOptions`] can hold (and clone, and print).
#[derive(Clone)]
pub struct Attach(pub Arc<MakeObserver>);

impl Attach {
    /// Wraps an observer maker.
    pub fn new(
        make: impl Fn(&RunStart<'_>) -> Result<Option<Box<dyn RunObserver>>, Error> + Send + Sync + 'static,
    ) -> Self {
        Self(Arc::new(make))
    }
}

impl std::fmt::Debug for Attach {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Attach(..)")
    }
}

/// What to run and where to write. `RunOptions { config, out: Some(dir), ..Default::default() }`
/// leaves everything else at its default (no force, no observers, no stop flag, no checkpoints).
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// The configuration (already validated).
    pub config: Config,
    /// Output folder; `None`: a fresh folder under `output.dir`.
    pub out: Option<PathBuf>,
    /// Allow writing into an existing non-empty `out`.
    pub force: bool,
    /// What watches the run beside its CSV files (pictures, progress), made once the simulation is
    /// set up; none: the run writes `results.csv`, `events.csv`, `impacts.csv` and `status.json`.
    pub observers: Vec<Attach>,
    /// When set (by a Ctrl-C or SIGTERM handler), the run stops at the next step boundary and
    /// finishes its outputs with what was computed ([`RunEnd::Interrupted`]).
    pub stop: Option<Arc<AtomicBool>>,
    /// Write the latest snapshot to [`CHECKPOINT_SNAP`] in the output folder every this many steps
    /// and when the run ends (completed or interrupted), with the configuration in
    /// [`CHECKPOINT_TOML`](crate::checkpoint::CHECKPOINT_TOML); `None`: no checkpoints.
    pub checkpoint_every: Option<usize>,
    /// Continue the run in `out` from its [`CHECKPOINT_SNAP`] (see [`run`]).
    pub restart: bool,
}

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
    /// Warnings the run raised (each also printed to stderr when raised): the reduced body's
    /// when it does not apply ([`pendulum_fem_core::reduced::validity`]).
    pub warnings: Vec<String>,
    /// A reduced body's largest error estimate over the run and its time `(η, t)`.
    pub error_estimate: Option<(f64, f64)>,
    /// Final proxy angle \[rad\].
    pub theta_final: f64,
    /// Smallest and largest proxy angle \[rad\].
    pub theta_range: (f64, f64),
    /// Period from zero crossings \[s\]; `None` when the head struck a wall (see
    /// [`RunSummary::impacts`]).
    pub period: Option<f64>,
    /// Largest von Mises stress over the run \[Pa\].
    pub von_mises_max: f64,
    /// With a wall: the impacts and the largest contact force \[N\] over the records (a restarted
    /// run's earlier ones included) and the events' peaks between them; what a study's row reports.
    pub contact: Option<(usize, f64)>,
    /// With a wall: count, interval, restitution and rebound of the impacts (what the summary
    /// reports instead of [`RunSummary::period`], which zero crossings inside the impacts spoil).
    pub impacts: Option<ImpactSummary>,
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
        let model = pendulum_fem_core::simulation::Model::new(&opts.config, mesh::generate(&opts.config)?)?;
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
    run_with(opts, out_dir, |_, _| Ok(()))
}

impl RunSummary {
    /// Takes a record into the run's figures: θ's range and last value, the period, the largest
    /// von Mises stress and, with a wall, the impacts and the largest contact force (the record's
    /// and the peaks between the records, in `events`, the contact events up to the record). The
    /// one tally for a run's records and a restarted run's records before its checkpoint.
    fn take_record(
        &mut self,
        period: &mut PeriodEstimator,
        impacts: &mut ImpactSummary,
        r: &StepRecord,
        events: &[ContactEvent],
    ) {
        period.push(r.time, r.theta);
        self.theta_range.0 = self.theta_range.0.min(r.theta);
        self.theta_range.1 = self.theta_range.1.max(r.theta);
        self.von_mises_max = self.von_mises_max.max(r.von_mises_max);
        self.theta_final = r.theta;
        if let Some(c) = &r.contact {
            impacts.observe(events, r.theta);
            let peaks = events.iter().map(|e| e.force).fold(0.0, f64::max);
            let largest = self.contact.map_or(0.0, |(_, f)| f);
            self.contact = Some((c.impacts, largest.max(c.force).max(peaks)));
        }
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

/// Runs the simulation into `out_dir` with the observers of `opts`, calling `observe` after every
/// record (step 0 included) with the simulation and the record.
///
/// Whatever happens, the folder stays consistent: `status.json` says `"running"` from the start
/// and `"ok"`, `"interrupted"` or `"failed"` (with the error) at the end, with the last step and
/// time reached. When a step fails or the run is interrupted, `results.csv` is complete up to the
/// last step computed, that step is written as the last frame, and the plots, animations and
/// viewer show what was computed; a failure is then returned as the error.
pub fn run_with(
    opts: &RunOptions,
    out_dir: PathBuf,
    observe: impl FnMut(&Simulation, &StepRecord) -> Result<(), Error>,
) -> Result<RunSummary, Error> {
    let status_path = out_dir.join(crate::status::STATUS_JSON);
    let end_time = opts.config.time.end;
    crate::status::RunStatus::running(end_time).write(&status_path)?;
    let mut reached = None;
    let result = run_steps(opts, out_dir, observe, &mut reached);
    let status = match &result {
        Ok(s) if s.end == RunEnd::Interrupted => {
            crate::status::RunStatus::interrupted(end_time, reached).with_warnings(&s.warnings)
        }
        Ok(s) => crate::status::RunStatus::ok(end_time, reached).with_warnings(&s.warnings),
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
    let header = crate::rows::header(sim.model.wall.is_some());
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
            let path = out_dir.join(crate::outdir::names::IMPACTS_CSV);
            Some(match opts.restart && path.is_file() {
                true => {
                    cut_rows_after(&path, sim.time())?;
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
        unknowns: sim.model.unknowns(),
        theta_range: (f64::INFINITY, f64::NEG_INFINITY),
        ..Default::default()
    };
    let start_of = RunStart {
        config: cfg,
        sim: &sim,
        out_dir: &out_dir,
        resumed: &earlier_times,
    };
    let mut observers = Vec::with_capacity(opts.observers.len());
    for attach in &opts.observers {
        observers.extend((attach.0)(&start_of)?);
    }
    let mut seconds_outputs = 0.0;
    let mut period = PeriodEstimator::default();
    let mut impacts = ImpactSummary::default();
    let mut audit = EnergyAudit::of(&sim.model);
    let plan = StepPlan::of(&cfg.time);
    summary.last_step = plan.last;
    let stop_requested = || opts.stop.as_ref().is_some_and(|s| s.load(Ordering::SeqCst));
    for r in &earlier {
        // the events up to this record, as the record saw them when it was first written
        let events = sim.contact_events();
        let seen = &events[..events.partition_point(|e| e.time <= r.time)];
        summary.take_record(&mut period, &mut impacts, r, seen);
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
        let t_out = Instant::now();
        if let Err(e) = observers
            .iter_mut()
            .try_for_each(|o| o.record(&mut sim, &record, resumed))
        {
            break Err(e);
        }
        seconds_outputs += t_out.elapsed().as_secs_f64();
        if let Err(e) = observe(&sim, &record) {
            break Err(e);
        }
        summary.take_record(&mut period, &mut impacts, &record, sim.contact_events());
        let error = audit.push(&record);
        if cfg.output.energy_watchdog > 0.0 && error > cfg.output.energy_watchdog {
            break Err(audit.divergence(&record, cfg.output.energy_watchdog));
        }
        if let Some(every) = opts.checkpoint_every {
            if sim.step.is_multiple_of(every.max(1)) && !resumed {
                // every row and frame up to this step on disk first, then the snapshot
                let written = csv
                    .flush()
                    .and_then(|()| observers.iter_mut().try_for_each(|o| o.sync()));
                if let Err(e) = written.and_then(|()| write_checkpoint(&out_dir, &sim)) {
                    break Err(e);
                }
            }
        }
        resumed = false;
        if let Some(w) = sim.take_warning() {
            eprintln!("{w}");
            summary.warnings.push(w);
        }
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
    // Finish every output with what was computed; the first error wins.
    let mut first_error = stopped.err();
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
    let t_out = Instant::now();
    for observer in observers {
        match observer.finish(&mut sim, &record) {
            Ok(paths) => summary.files.extend(paths),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    seconds_outputs += t_out.elapsed().as_secs_f64();
    if let Some(e) = first_error {
        return Err(e);
    }
    summary.seconds_outputs = seconds_outputs;
    summary.steps = sim.step;
    summary.error_estimate = sim.error_estimate();
    summary.time_reached = sim.time();
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
