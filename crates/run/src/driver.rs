//! `pendulum-fem run`: mesh, simulate, stream `results.csv`, summarise, and leave a consistent run
//! folder however the run ends (completed, interrupted at a step boundary, or failed; see
//! [`run_with`]). What else watches the run (the pictures and ParaView frames, a progress bar) is a
//! [`RunObserver`], attached through [`RunOptions::observers`].

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use pendulum_fem_core::config::{StepPlan, Time};
use pendulum_fem_core::post::PeriodEstimator;
use pendulum_fem_core::simulation::{Built, ContactEvent, Simulation, StepRecord};
use pendulum_fem_core::{Config, Error, Snapshot};

use crate::audit::EnergyAudit;
use crate::checkpoint::{
    events_until, impacts_until, read_checkpoint, resume, write_checkpoint, write_checkpoint_config, CHECKPOINT_SNAP,
};
use crate::csv::CsvWriter;
use crate::impacts::ImpactSummary;
use crate::outdir::names;
use crate::prepare_output_dir;
use crate::rows::{csv_values, event_row, EVENTS_HEADER};

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
    /// A restarted run: the records its folder holds from before the checkpoint, the rows of
    /// `results.csv` before the checkpoint's and those of `impacts.csv`, in time order (what
    /// [`RunObserver::record`] and [`RunObserver::substeps`] took before the run was stopped);
    /// empty for a fresh run.
    pub earlier: &'a [StepRecord],
}

/// Something that watches a run beside its CSV files: the pictures and ParaView frames
/// (`pendulum-fem-render`), the CLI's progress bar. The driver calls it in this order:
/// [`RunObserver::record`] for every record (the rows of `results.csv`), after each step's
/// [`RunObserver::substeps`] (the rows it adds to `impacts.csv`), [`RunObserver::sync`] before each
/// checkpoint, and [`RunObserver::finish`] once at the end, whether the run completed, was
/// interrupted or failed. The records so come in time order.
pub trait RunObserver {
    /// Takes the record of the latest step (step 0's first). `resumed`: the record is a restarted
    /// run's checkpoint, whose outputs its folder already holds.
    fn record(&mut self, sim: &mut Simulation, record: &StepRecord, resumed: bool) -> Result<(), Error>;

    /// Takes the records of the sub-steps inside an impact that the step just taken wrote to
    /// `impacts.csv` ([`Simulation::record_impacts`]), before that step's [`RunObserver::record`].
    fn substeps(&mut self, records: &[StepRecord]) -> Result<(), Error> {
        let _ = records;
        Ok(())
    }

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
/// snapshot is decoded and the model built once, and a snapshot of another model is refused before
/// anything in the folder is touched. The rows of `results.csv` after the checkpoint's step are
/// dropped (they are computed again; the checkpoint's own row must equal the restored state's, bit
/// for bit), as are the rows of `impacts.csv` after its time and those of `events.csv` after its
/// events; the ParaView frames up to it stay in `pendulum.pvd`, and all are appended to, so that
/// the files are byte for byte those of an uninterrupted run with the same steps. The animations
/// and the viewer show the frames from the checkpoint on; the plots show the whole run, the
/// records before the checkpoint read back from `results.csv` and `impacts.csv`. A run finished on
/// a shortened last step (`time.end` off the `time.dt` grid) continues from there with steps of
/// `time.dt`, which an uninterrupted run would not have taken.
pub fn run(opts: &RunOptions) -> Result<RunSummary, Error> {
    if !opts.restart {
        let out_dir = prepare_output_dir(&opts.config.output.dir, opts.out.as_deref(), opts.force)?;
        return run_with(opts, out_dir, |_, _| Ok(()));
    }
    let dir = opts
        .out
        .clone()
        .ok_or_else(|| Error::Input("run --restart: name the folder of the run to continue".into()))?;
    if !dir.join(CHECKPOINT_SNAP).is_file() {
        return Err(Error::Input(format!(
            "run --restart {}: no {CHECKPOINT_SNAP} there (a run writes it with --checkpoint-every N)",
            dir.display()
        )));
    }
    // refuse another model before anything in the folder is touched
    let set_up = SetUp::of(opts, &dir)?;
    run_set_up(opts, dir, Some(set_up), |_, _| Ok(()))
}

/// A run's simulation, built, and for a restart the checkpoint it continues from.
struct SetUp {
    /// The simulation at its initial state, with the time its mesh and set-up took.
    built: Built,
    /// The checkpoint of a restarted run, checked against the simulation's model.
    checkpoint: Option<Snapshot>,
    /// When the set-up began (the run's total time counts from there).
    began: Instant,
}

impl SetUp {
    /// Builds the simulation of `opts.config` and, for a restart, reads the checkpoint in `dir`
    /// and checks that it was made for this model.
    fn of(opts: &RunOptions, dir: &Path) -> Result<Self, Error> {
        let began = Instant::now();
        let checkpoint = match opts.restart {
            true => Some(read_checkpoint(dir)?),
            false => None,
        };
        #[cfg(test)]
        tests::SET_UPS.with(|n| n.set(n.get() + 1));
        let built = Simulation::build(&opts.config)?;
        if let Some(snapshot) = &checkpoint {
            // the model's own fingerprint (with its torque table and, with a deformable wall, the block)
            let model = built.simulation.model.fingerprint;
            if let Some(parts) = snapshot.fingerprint().differences(&model, &opts.config) {
                return Err(Error::Input(format!(
                    "{}: made for another model: {parts} (fingerprint {}; this configuration gives {model}): \
                     restart with the configuration of the run (only time.end and [output] may change)",
                    dir.join(CHECKPOINT_SNAP).display(),
                    snapshot.fingerprint(),
                )));
            }
        }
        Ok(Self {
            built,
            checkpoint,
            began,
        })
    }
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
    run_set_up(opts, out_dir, None, observe)
}

/// [`run_with`] with the simulation set up already (a restart's, checked against its checkpoint
/// before the folder was touched) or, `None`, set up once `status.json` says `"running"`.
fn run_set_up(
    opts: &RunOptions,
    out_dir: PathBuf,
    set_up: Option<SetUp>,
    observe: impl FnMut(&Simulation, &StepRecord) -> Result<(), Error>,
) -> Result<RunSummary, Error> {
    let status_path = out_dir.join(crate::status::STATUS_JSON);
    let end_time = opts.config.time.end;
    crate::status::RunStatus::running(end_time).write(&status_path)?;
    let mut reached = None;
    let result = set_up
        .map_or_else(|| SetUp::of(opts, &out_dir), Ok)
        .and_then(|set_up| run_steps(opts, out_dir, set_up, observe, &mut reached));
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

/// The steps of a run along a [`StepPlan`]: step `first + i` of the simulation is the plan's
/// `i`-th, of `dt` while `i < plan.full`, else the shortened last one that lands on `end`. The
/// one rule of the driver's runs (restarted ones too) and the Python package's `run`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanSteps {
    /// The plan.
    pub plan: StepPlan,
    dt: f64,
    end: f64,
    first: usize,
}

impl PlanSteps {
    /// The steps of a run of `time` from step 0 at time 0 (a restarted run too: its steps keep
    /// their numbers).
    pub fn of(time: &Time) -> Self {
        Self {
            plan: StepPlan::of(time),
            dt: time.dt,
            end: time.end,
            first: 0,
        }
    }

    /// The steps from the state of `sim` now to the time `end` \[s\] in steps of `dt`.
    pub fn from_now(sim: &Simulation, dt: f64, end: f64) -> Self {
        let time = Time {
            dt,
            end: end - sim.time(),
            ..Time::default()
        };
        Self {
            plan: StepPlan::of(&time),
            dt,
            end,
            first: sim.step,
        }
    }

    /// Whether `sim` has taken every step of the plan.
    pub fn done(&self, sim: &Simulation) -> bool {
        sim.step >= self.first + self.plan.steps()
    }

    /// Takes the next step of the plan; returns its Newton iterations.
    pub fn take(&self, sim: &mut Simulation) -> Result<usize, Error> {
        match sim.step < self.first + self.plan.full {
            true => sim.step(self.dt),
            false => sim.step_to(self.end),
        }
    }

    /// Walks `sim` along the plan: hands the record of the state now, then that of every step, to
    /// `take`, and ends after the plan's last step ([`RunEnd::Completed`]) or, when `stop` says so
    /// after a record, at that step boundary ([`RunEnd::Interrupted`]). Returns the last record
    /// handed over and how the walk ended: the error of a step (the record before it is the last)
    /// or of `take` ends it too.
    pub fn walk(
        &self,
        sim: &mut Simulation,
        mut take: impl FnMut(&mut Simulation, &StepRecord) -> Result<(), Error>,
        mut stop: impl FnMut() -> bool,
    ) -> (StepRecord, Result<RunEnd, Error>) {
        let mut record = sim.record(sim.last_newton_iterations());
        loop {
            if let Err(e) = take(sim, &record) {
                return (record, Err(e));
            }
            if self.done(sim) {
                return (record, Ok(RunEnd::Completed));
            }
            if stop() {
                return (record, Ok(RunEnd::Interrupted));
            }
            // the stepper advances; the record (with the nodal stresses) is the walk's observation
            match self.take(sim) {
                Ok(its) => record = sim.record(its),
                Err(e) => return (record, Err(e)),
            }
        }
    }
}

/// The run proper; `reached` follows the last step written to `results.csv` (step, time).
fn run_steps(
    opts: &RunOptions,
    out_dir: PathBuf,
    set_up: SetUp,
    mut observe: impl FnMut(&Simulation, &StepRecord) -> Result<(), Error>,
    reached: &mut Option<(usize, f64)>,
) -> Result<RunSummary, Error> {
    let cfg = &opts.config;
    let SetUp {
        built,
        checkpoint,
        began,
    } = set_up;
    if let Some(warning) = &built.mesh_warning {
        eprintln!("{warning}");
    }
    let mut sim = built.simulation;
    let t_steps = Instant::now();
    let wall = sim.model.wall.is_some();
    let header = crate::rows::header(wall);
    let csv_path = out_dir.join(names::RESULTS_CSV);
    let events_path = out_dir.join(names::EVENTS_CSV);
    let impacts_path = out_dir.join(names::IMPACTS_CSV);
    // A restarted run returns to its checkpoint; the records before it feed the summary and the
    // observers. With a wall, the sub-steps inside impacts go to impacts.csv (the columns of
    // results.csv) and the contact events to events.csv.
    sim.record_impacts(wall);
    // the contact events in events.csv already
    let mut events_written = 0;
    let (resumed_rows, resumed_times, earlier) = match &checkpoint {
        Some(snapshot) => {
            let resumed = resume(&out_dir, &mut sim, snapshot)?;
            let (substeps, impacts_cut) = match wall && impacts_path.is_file() {
                true => impacts_until(&impacts_path, sim.time()).map(|(kept, cut)| (kept, Some(cut)))?,
                false => (Vec::new(), None),
            };
            let events_cut = match wall && events_path.is_file() {
                true => Some(events_until(&events_path, sim.contact_events())?),
                false => None,
            };
            if events_cut.is_some() {
                events_written = sim.contact_events().len();
            }
            // every file checked: cut them
            for cut in [Some(resumed.cut), impacts_cut, events_cut].into_iter().flatten() {
                cut.apply()?;
            }
            // one list in time order, the rows of results.csv first where times tie
            let mut earlier: Vec<StepRecord> = resumed.rows.iter().cloned().chain(substeps).collect();
            earlier.sort_by(|a, b| a.time.total_cmp(&b.time));
            (resumed.rows, resumed.times, earlier)
        }
        None => Default::default(),
    };
    if opts.checkpoint_every.is_some() {
        write_checkpoint_config(&out_dir, cfg)?;
    }
    let open = |path: &Path, header: &str| match checkpoint.is_some() && path.is_file() {
        true => CsvWriter::append(path, header),
        false => CsvWriter::create(path, header),
    };
    let mut csv = open(&csv_path, &header)?;
    let mut impacts_csv = wall.then(|| open(&impacts_path, &header)).transpose()?;
    // events.csv gets a row per contact event as it happens (a restarted run's from its checkpoint on)
    let mut events_csv = wall.then(|| open(&events_path, EVENTS_HEADER)).transpose()?;
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
        resumed: &resumed_times,
        earlier: &earlier,
    };
    let mut observers = Vec::with_capacity(opts.observers.len());
    for attach in &opts.observers {
        observers.extend((attach.0)(&start_of)?);
    }
    let mut seconds_outputs = 0.0;
    let mut period = PeriodEstimator::default();
    let mut impacts = ImpactSummary::default();
    let mut audit = EnergyAudit::of(&sim.model);
    let steps = PlanSteps::of(&cfg.time);
    summary.last_step = steps.plan.last;
    for r in &resumed_rows {
        // the events up to this record, as the record saw them when it was first written
        let events = sim.contact_events();
        let seen = &events[..events.partition_point(|e| e.time <= r.time)];
        summary.take_record(&mut period, &mut impacts, r, seen);
        audit.push(r);
    }
    // a restarted run's first record (the checkpoint's) is in results.csv and the frames already
    let mut resumed = checkpoint.is_some();
    // The walk ends completed, interrupted or with the error that stopped it; the outputs of what
    // was computed are finished either way.
    let (record, walked) = steps.walk(
        &mut sim,
        |sim, record| {
            let substeps = sim.take_impact_records();
            if let Some(w) = impacts_csv.as_mut() {
                substeps.iter().try_for_each(|r| w.row(&csv_values(r)))?;
            }
            if !resumed {
                csv.row(&csv_values(record))?;
            }
            if let Some(w) = events_csv.as_mut() {
                let events = sim.contact_events();
                if events.len() > events_written {
                    events[events_written..]
                        .iter()
                        .try_for_each(|e| w.line(&event_row(e)))?;
                    // a few rows a run: on disk at once, for whoever watches the folder
                    w.flush()?;
                    events_written = events.len();
                }
            }
            *reached = Some((record.step, record.time));
            let t_out = Instant::now();
            for o in observers.iter_mut() {
                if !substeps.is_empty() {
                    o.substeps(&substeps)?;
                }
                o.record(sim, record, resumed)?;
            }
            seconds_outputs += t_out.elapsed().as_secs_f64();
            observe(sim, record)?;
            summary.take_record(&mut period, &mut impacts, record, sim.contact_events());
            let error = audit.push(record);
            if cfg.output.energy_watchdog > 0.0 && error > cfg.output.energy_watchdog {
                return Err(audit.divergence(record, cfg.output.energy_watchdog));
            }
            if let Some(every) = opts.checkpoint_every {
                if sim.step.is_multiple_of(every.max(1)) && !resumed {
                    // every row and frame up to this step on disk first, then the snapshot
                    csv.flush()?;
                    for w in impacts_csv.iter_mut().chain(events_csv.iter_mut()) {
                        w.flush()?;
                    }
                    observers.iter_mut().try_for_each(|o| o.sync())?;
                    write_checkpoint(&out_dir, sim)?;
                }
            }
            resumed = false;
            if let Some(w) = sim.take_warning() {
                eprintln!("{w}");
                summary.warnings.push(w);
            }
            Ok(())
        },
        || opts.stop.as_ref().is_some_and(|s| s.load(Ordering::SeqCst)),
    );
    // Finish every output with what was computed; the first error wins.
    let mut first_error = None;
    match walked {
        Ok(end) => summary.end = end,
        Err(e) => first_error = Some(e),
    }
    for w in [events_csv, impacts_csv, Some(csv)].into_iter().flatten() {
        match w.finish() {
            Ok(path) => summary.files.push(path),
            Err(e) => {
                first_error.get_or_insert(e);
            }
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
    if wall {
        impacts.of_events(sim.contact_events());
        summary.impacts = Some(impacts);
    }
    // a head that struck the wall crosses θ = 0 only inside the impacts: no period (the summary
    // reports the impacts, a sweep's summary.csv leaves `period_s` empty)
    summary.period = period.period().filter(|_| summary.impacts.is_none_or(|i| i.count == 0));
    summary.energy_error = audit.error();
    summary.energy_scale = audit.scale();
    summary.timings = sim.timings();
    summary.seconds_mesh = built.mesh_seconds;
    summary.seconds_setup = built.setup_seconds;
    summary.seconds_steps = t_steps.elapsed().as_secs_f64();
    summary.seconds_total = began.elapsed().as_secs_f64();
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use std::cell::Cell;

    use super::*;

    thread_local! {
        /// The set-ups of this thread's runs ([`SetUp::of`]: each builds the simulation once and
        /// decodes a restart's checkpoint once).
        pub(super) static SET_UPS: Cell<usize> = const { Cell::new(0) };
    }

    #[test]
    fn a_restart_decodes_its_checkpoint_and_builds_its_simulation_once() {
        let dir = std::env::temp_dir().join(format!("pendulum-fem-restart-once-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let mut config = Config::default();
        config.time.end = 2.0 * config.time.dt;
        let opts = RunOptions {
            config,
            out: Some(dir.clone()),
            checkpoint_every: Some(1),
            ..Default::default()
        };
        run(&opts).unwrap();
        let mut opts = RunOptions { restart: true, ..opts };
        opts.config.time.end = 3.0 * opts.config.time.dt;
        let before = SET_UPS.with(Cell::get);
        let summary = run(&opts).unwrap();
        assert_eq!(SET_UPS.with(Cell::get) - before, 1, "one set-up for the restart");
        assert_eq!((summary.steps, summary.end), (3, RunEnd::Completed));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn the_steps_of_a_plan_from_now_land_on_its_end_with_a_shortened_last_step() {
        let mut config = Config::default();
        config.time.end = 0.0;
        let mut sim = Simulation::build(&config).unwrap().simulation;
        let (dt, end) = (0.01, 0.025);
        let steps = PlanSteps::from_now(&sim, dt, end);
        assert_eq!((steps.plan.full, steps.plan.steps()), (2, 3));
        let mut times = Vec::new();
        let (last, walked) = steps.walk(
            &mut sim,
            |_, r| {
                times.push(r.time);
                Ok(())
            },
            || false,
        );
        assert_eq!(walked.unwrap(), RunEnd::Completed);
        assert_eq!(times, [0.0, 0.01, 0.02, end]);
        assert_eq!(last.time, end);
        // from there, one more step of dt; asked to stop, the walk stops before it
        let steps = PlanSteps::from_now(&sim, dt, end + dt);
        let (_, walked) = steps.walk(&mut sim, |_, _| Ok(()), || true);
        assert_eq!((walked.unwrap(), sim.step), (RunEnd::Interrupted, 3));
        let (last, walked) = steps.walk(&mut sim, |_, _| Ok(()), || false);
        assert_eq!((walked.unwrap(), sim.step, last.time), (RunEnd::Completed, 4, end + dt));
    }
}
