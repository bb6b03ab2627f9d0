//! `pendulum-fem run`: mesh, simulate, stream `results.csv`, summarise, and leave a consistent run
//! folder however the run ends (completed, interrupted at a step boundary, or failed; see
//! [`run_with`]). What else watches the run (the pictures and ParaView frames, a progress bar) is a
//! [`RunObserver`], attached through [`RunOptions::observers`].

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use pendulum_fem_core::post::PeriodEstimator;
use pendulum_fem_core::simulation::{Built, Simulation, StepRecord};
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

mod observer;
mod plan;
mod summary;

pub use observer::{Attach, MakeObserver, RunObserver, RunStart};
pub use plan::PlanSteps;
pub use summary::{RunEnd, RunSummary};

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
    /// Warnings about the configuration, already shown (the keys without effect,
    /// [`Config::ineffective_keys`]): the run keeps them with its own in its summary and
    /// `status.json`.
    pub warnings: Vec<String>,
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
    crate::status::RunStatus::running(end_time)
        .with_warnings(&opts.warnings)
        .write(&status_path)?;
    let mut reached = None;
    let result = set_up
        .map_or_else(|| SetUp::of(opts, &out_dir), Ok)
        .and_then(|set_up| run_steps(opts, out_dir, set_up, observe, &mut reached));
    let status = match &result {
        Ok(s) if s.end == RunEnd::Interrupted => {
            crate::status::RunStatus::interrupted(end_time, reached).with_warnings(&s.warnings)
        }
        Ok(s) => crate::status::RunStatus::ok(end_time, reached).with_warnings(&s.warnings),
        Err(e) => crate::status::RunStatus::failed(end_time, reached, e).with_warnings(&opts.warnings),
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
        warnings: opts.warnings.clone(),
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
        audit.push(r)?;
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
            // a finite error: a NaN or an infinity stopped the run already, watchdog or not
            let error = audit.push(record)?;
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
