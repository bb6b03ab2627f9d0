//! Command-line interface of pendulum-fem: parses arguments, calls the library, prints results and
//! errors. Errors go to stderr with a non-zero exit code.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use clap::{Args, Parser, Subcommand};
use pendulum_fem::commands::run::{RunEnd, RunOptions};
use pendulum_fem::{config, Config, Error};

/// Finite-element simulation of a deformable pendulum (the NGSolve tutorial "FEM Pendulum").
///
/// Without a subcommand, `run` is executed with the built-in defaults.
#[derive(Parser, Debug)]
#[command(name = "pendulum-fem", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Simulate the swing and write results.csv (and the other outputs) to a fresh folder.
    Run(RunArgs),
    /// Mesh the pendulum and write mesh.vtu/mesh.vtm (ParaView) and mesh.msh (Gmsh 4.1).
    Mesh {
        #[command(flatten)]
        cfg: ConfigArgs,
        /// Output folder (default: `mesh`).
        #[arg(long, short = 'o', value_name = "DIR", default_value = "mesh")]
        out: PathBuf,
        /// Print the summary as one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Natural frequencies and mode shapes of the pinned pendulum about the undeformed state:
    /// a table, DIR/modes.json, DIR/modes.pvd (one .vtu per mode) and DIR/modes.png.
    Modes(ModesArgs),
    /// Measure speed and memory (see `pendulum-fem bench --help`).
    Bench(BenchArgs),
    /// Run a parameter study: one run per case, in parallel or as job-array tasks, and a summary
    /// table DIR/summary.csv with figures (docs/src/studies.md).
    Sweep(SweepArgs),
    /// Write a commented configuration file listing every key, its default and its unit.
    Init {
        /// File to write (default: pendulum.toml).
        file: Option<PathBuf>,
        /// Overwrite an existing file.
        #[arg(long)]
        force: bool,
    },
}

/// Options shared by the commands that read a configuration.
#[derive(Args, Debug, Default, Clone)]
struct ConfigArgs {
    /// TOML configuration file (every key optional; omitted: the tutorial's defaults).
    #[arg(long, short = 'c', value_name = "FILE")]
    config: Option<PathBuf>,
    /// Override a configuration key, e.g. `--set mesh.refine=2` or `--set time.end=3` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

#[derive(Args, Debug, Default)]
struct RunArgs {
    #[command(flatten)]
    cfg: ConfigArgs,
    /// Output folder (default: a fresh numbered folder under `output.dir`).
    #[arg(long, short = 'o', value_name = "DIR")]
    out: Option<PathBuf>,
    /// Allow --out to name an existing non-empty folder.
    #[arg(long)]
    force: bool,
    /// Print nothing on success: no progress and no summary (warnings and errors still go to
    /// stderr; the exit code tells how the run ended).
    #[arg(long, short = 'q')]
    quiet: bool,
    /// Write the latest snapshot to checkpoint.snap in the results folder every N steps (and at
    /// the end), for `--restart`.
    #[arg(long, value_name = "N")]
    checkpoint_every: Option<usize>,
    /// Continue the run in DIR from its checkpoint.snap, appending to its results.csv and
    /// pendulum.pvd (the configuration from DIR/checkpoint.toml; `--set time.end=…` runs longer).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["out", "force", "config"])]
    restart: Option<PathBuf>,
}

/// `modes`: the folder is picked as `run` picks its own.
#[derive(Args, Debug)]
struct ModesArgs {
    #[command(flatten)]
    cfg: ConfigArgs,
    /// Elastic modes to compute besides the rigid rotation (1 to 50).
    #[arg(long, value_name = "N", default_value_t = 10, allow_negative_numbers = true)]
    n: i64,
    /// Output folder (default: a fresh numbered folder `modes-NNNN` under `output.dir`).
    #[arg(long, short = 'o', value_name = "DIR")]
    out: Option<PathBuf>,
    /// Allow --out to name an existing non-empty folder (the files of an earlier `modes` there are
    /// removed first, other files are kept).
    #[arg(long)]
    force: bool,
    /// Print the report as one JSON object (the content of modes.json).
    #[arg(long)]
    json: bool,
}

/// `sweep`: the cases come from `--vary` (and `--file`); each runs in DIR/case-NNNN.
#[derive(Args, Debug)]
struct SweepArgs {
    #[command(flatten)]
    cfg: ConfigArgs,
    /// Vary a configuration key (any depth): KEY=VALUES with VALUES a list `1e6,1e7,2.1e11`, a
    /// linear range `10:60:6` (start:stop:count) or a log range `1e6..2.1e11:8`
    /// (start..stop:count). Several form the full grid, the first varying slowest (repeatable).
    #[arg(long, value_name = "KEY=VALUES")]
    vary: Vec<String>,
    /// Pair the values of the --vary keys (the k-th of each) instead of forming the grid.
    #[arg(long)]
    zip: bool,
    /// A sweep file (TOML): `[vary]` (KEY = "VALUES" or a list) or `[[case]]` tables, and optional
    /// `config`, `set`, `zip` (see docs/src/studies.md).
    #[arg(long, value_name = "FILE")]
    file: Option<PathBuf>,
    /// Sweep folder: DIR/cases.csv, DIR/case-NNNN/, DIR/summary.csv, DIR/summary_*.png.
    #[arg(long, short = 'o', value_name = "DIR", default_value = "sweep")]
    out: PathBuf,
    /// Cases run at once (default: the number of cores).
    #[arg(long, short = 'j', value_name = "N")]
    jobs: Option<usize>,
    /// Threads per case (element loops, sparse factorisation).
    #[arg(long, value_name = "N", default_value_t = 1)]
    threads: usize,
    /// Continue the sweep in --out: finished cases (ok or failed) are kept, the others run.
    #[arg(long)]
    resume: bool,
    /// Print the number of cases and exit (for `--array=0-$((N-1))`).
    #[arg(long, conflicts_with_all = ["resume", "case_index"])]
    list: bool,
    /// Run case K only (0 to N-1), a job-array task; `--gather` builds the summary afterwards.
    /// Without it, taken from SLURM_ARRAY_TASK_ID, PBS_ARRAY_INDEX or LSB_JOBINDEX - 1 when set.
    #[arg(long, value_name = "K")]
    case_index: Option<usize>,
    /// Build DIR/summary.csv and the figures from the case folders of the sweep in DIR.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["vary", "file", "zip", "list", "case_index", "resume", "config", "set"])]
    gather: Option<PathBuf>,
    /// Keep the plots, animations, ParaView frames and viewer the configuration asks for in every
    /// case (default: only results.csv, status.json, config.toml and the case's summary row).
    #[arg(long)]
    all_outputs: bool,
    /// No summary_*.png figures.
    #[arg(long)]
    no_plots: bool,
    /// No progress output.
    #[arg(long, short = 'q')]
    quiet: bool,
}

/// The case index of a job-array task from the scheduler's environment: Slurm's and PBS's as they
/// are (submit `--array=0-<N-1>`, `-J 0-<N-1>`), LSF's minus one (its indices start at 1; a job
/// that is no array has `LSB_JOBINDEX=0`).
fn array_index() -> Result<Option<(usize, &'static str)>, Error> {
    for (var, offset) in [("SLURM_ARRAY_TASK_ID", 0), ("PBS_ARRAY_INDEX", 0), ("LSB_JOBINDEX", 1)] {
        let Ok(text) = std::env::var(var) else { continue };
        let k: usize = text
            .trim()
            .parse()
            .map_err(|_| Error::Config(format!("{var}={text}: not a case index (a whole number >= {offset})")))?;
        if offset == 1 && k == 0 {
            continue;
        }
        return Ok(Some((k - offset, var)));
    }
    Ok(None)
}

fn sweep(args: SweepArgs) -> Result<ExitCode, Error> {
    use pendulum_fem::commands::sweep::{self as sw, CaseOptions, CaseStatus, Sweep, SweepOptions};
    if let Some(dir) = &args.gather {
        let r = sw::gather(dir, !args.no_plots)?;
        println!(
            "pendulum-fem sweep --gather: {} cases, {} ok, {} failed, {} without a result; summary in {}",
            r.cases,
            r.ok,
            r.failed.len(),
            r.pending.len(),
            r.summary.display()
        );
        return Ok(sweep_exit(&r.failed, &r.pending, r.cases, &r.summary));
    }
    if args.jobs == Some(0) || args.threads == 0 {
        return Err(Error::Config(
            "sweep --jobs / --threads 0: allowed N >= 1 (--jobs defaults to the number of cores)".into(),
        ));
    }
    let mut study = Sweep::new(
        args.cfg.config.clone(),
        args.cfg.set.clone(),
        &args.vary,
        args.zip,
        args.file.as_deref(),
    )?;
    study.all_outputs = args.all_outputs;
    for w in study.ineffective_keys() {
        eprintln!("warning: {w}");
    }
    if args.list {
        println!("{}", study.len());
        return Ok(ExitCode::SUCCESS);
    }
    let stop = Arc::new(AtomicBool::new(false));
    let index = match args.case_index {
        Some(k) => Some(k),
        None => array_index()?.map(|(k, var)| {
            if !args.quiet {
                eprintln!("sweep: case {k} (from {var}); --case-index K names one explicitly");
            }
            k
        }),
    };
    if let Some(k) = index {
        install_stop_handler(stop.clone(), "stopping the case after the current step");
        let opts = CaseOptions {
            threads: args.threads,
            stop: Some(stop),
            observers: vec![pendulum_fem::render::pictures::attach()],
        };
        let row = sw::run_case_index(&study, &args.out, k, args.resume, &opts)?;
        let dir = sw::case_dir(&args.out, k);
        return Ok(match &row.status {
            CaseStatus::Failed(m) => {
                eprintln!(
                    "error: case {k} of {} failed: {m} (row in {})",
                    study.len(),
                    dir.display()
                );
                ExitCode::FAILURE
            }
            CaseStatus::Ok => {
                println!(
                    "pendulum-fem sweep: case {k} of {} ok in {:.3} s; results in {} (`sweep --gather {}` when all are done)",
                    study.len(),
                    row.metrics.wall_time_s.unwrap_or(0.0),
                    dir.display(),
                    args.out.display()
                );
                ExitCode::SUCCESS
            }
            _ => {
                eprintln!("case {k} interrupted; run it again (with --resume it is skipped once finished)");
                ExitCode::from(EXIT_INTERRUPTED)
            }
        });
    }
    install_stop_handler(
        stop.clone(),
        "stopping the running cases after their current step; finished cases and the summary are kept (--resume runs the rest)",
    );
    let opts = SweepOptions {
        out: args.out.clone(),
        jobs: args.jobs.unwrap_or(0),
        threads: args.threads,
        resume: args.resume,
        quiet: args.quiet,
        plots: !args.no_plots,
        stop: Some(stop),
    };
    let r = sw::run_sweep(&study, &opts)?;
    let minutes = r.seconds / 60.0;
    println!(
        "pendulum-fem sweep: {} cases ({} run now on {} workers, {} finished before), {} ok, {} failed, in {:.2} s ({:.1} cases per minute)",
        r.cases,
        r.ran,
        r.jobs,
        r.skipped,
        r.ok,
        r.failed.len(),
        r.seconds,
        if minutes > 0.0 { r.ran as f64 / minutes } else { 0.0 }
    );
    println!("  summary            {}", r.summary.display());
    for p in &r.plots {
        println!("  figure             {}", p.display());
    }
    if r.interrupted {
        eprintln!(
            "sweep interrupted: {} of {} cases finished; `pendulum-fem sweep … --out {} --resume` runs the rest",
            r.cases - r.pending.len(),
            r.cases,
            r.out.display()
        );
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
    }
    Ok(sweep_exit(&r.failed, &r.pending, r.cases, &r.summary))
}

/// Failure when any case failed or has no result, saying how many.
fn sweep_exit(failed: &[usize], pending: &[usize], cases: usize, summary: &std::path::Path) -> ExitCode {
    let list = |v: &[usize]| {
        let shown: Vec<String> = v.iter().take(20).map(|k| k.to_string()).collect();
        format!("{}{}", shown.join(", "), if v.len() > 20 { ", …" } else { "" })
    };
    if !failed.is_empty() {
        eprintln!(
            "error: {} of {cases} cases failed (cases {}; messages in {})",
            failed.len(),
            list(failed),
            summary.display()
        );
    }
    if !pending.is_empty() {
        eprintln!(
            "error: {} of {cases} cases have no result (cases {})",
            pending.len(),
            list(pending)
        );
    }
    if failed.is_empty() && pending.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

#[derive(Args, Debug)]
struct BenchArgs {
    /// What to measure.
    #[arg(value_enum, default_value = "run")]
    what: BenchTarget,
    #[command(flatten)]
    cfg: ConfigArgs,
    /// Repetitions of the default run (`run`, `modes`); the best is reported.
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Python interpreter with NGSolve: also time the tutorial script and print the ratio (`run`).
    #[arg(long, value_name = "PYTHON")]
    ngsolve: Option<PathBuf>,
    /// The NGSolve script of the tutorial's pendulum (shipped in this repository; run from its root).
    #[arg(long, value_name = "FILE", default_value = "scripts/ngsolve/pendulum_basics.py")]
    anchor: PathBuf,
    /// Steps per mesh (`scaling`).
    #[arg(long, default_value_t = 5)]
    steps: usize,
    /// Triangles of the large mesh (`mesh`).
    #[arg(long, default_value_t = 1_000_000)]
    triangles: usize,
    /// Largest problem of `scaling` in unknowns (targets 5k, 20k, 80k, 320k, ... up to this).
    #[arg(long, default_value_t = 320_000)]
    largest: usize,
    /// Python interpreter with fmpy (`fmu`; default: the one `scripts/test-env` prints).
    #[arg(long, value_name = "PYTHON")]
    python: Option<PathBuf>,
    /// The FMU to time (`fmu`; default: built by `cargo xtask fmu`).
    #[arg(long, value_name = "FILE")]
    fmu: Option<PathBuf>,
    /// Simulated seconds per communication step size (`fmu`).
    #[arg(long, default_value_t = 2.0)]
    seconds: f64,
    /// Run the FMU's reduced body (`model_kind = 1`; `fmu`).
    #[arg(long)]
    reduced: bool,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
enum BenchTarget {
    /// The whole default run, with a per-iteration breakdown.
    Run,
    /// Time per step from ~5k to ~320k unknowns.
    Scaling,
    /// Resident memory after 100 and 1000 steps.
    Memory,
    /// The tutorial mesh and a mesh of about `--triangles` triangles.
    Mesh,
    /// The cost per step of a follower torque (0.1 N m and 0 N m against none).
    Torque,
    /// 20 elastic modes of the pendulum (`pendulum-fem modes --n 20` without the files).
    Modes,
    /// The FMU through fmpy: real-time factors at communication steps of 10 ms and 1 ms.
    Fmu,
    /// The reduced body against the full model: a bare step at 1 ms, the default job (outputs off).
    Reduced,
}

fn bench(args: BenchArgs) -> Result<(), Error> {
    use pendulum_fem::commands::bench;
    let config = load(&args.cfg)?;
    match args.what {
        BenchTarget::Run => bench::bench_run(&config, args.repeats, args.ngsolve.as_deref(), &args.anchor),
        BenchTarget::Scaling => bench::bench_scaling(&config, args.steps, args.largest),
        BenchTarget::Memory => bench::bench_memory(&config, 100, 1000),
        BenchTarget::Mesh => pendulum_fem::mesh::bench::bench_mesh(&config, Some(args.triangles)).map(|_| ()),
        BenchTarget::Modes => bench::bench_modes(&config, 20, args.repeats).map(|_| ()),
        BenchTarget::Torque => [0.1, 0.0]
            .into_iter()
            .try_for_each(|m| bench::bench_torque(&config, 100, args.repeats, m).map(|_| ())),
        BenchTarget::Reduced => bench::bench_reduced(&config, args.repeats).map(|_| ()),
        BenchTarget::Fmu => bench::bench_fmu(
            args.python.as_deref(),
            args.fmu.as_deref(),
            args.seconds,
            args.repeats,
            args.reduced,
        )
        .map(|_| ()),
    }
}

fn modes(args: &ModesArgs) -> Result<(), Error> {
    use pendulum_fem::commands::modes::{check_count, modes_command, MAX_MODES};
    use pendulum_fem::commands::run::outdir::MODES_OUTPUTS;
    let n = args.n;
    let n = usize::try_from(n).map_err(|_| {
        Error::Input(format!(
            "modes --n {n}: allowed 1 to {MAX_MODES} (the number of elastic modes besides the rigid rotation)"
        ))
    })?;
    check_count(n)?;
    let config = load(&args.cfg)?;
    let out = MODES_OUTPUTS.prepare(&config.output.dir, args.out.as_deref(), args.force)?;
    let report = modes_command(&config, n, &out)?;
    if args.json {
        println!("{}", report.to_json());
    } else {
        print!("{}", report.table());
        println!(
            "written to {}: modes.json, modes.pvd (modes/mode_NN.vtu), modes.png",
            out.display()
        );
    }
    Ok(())
}

/// Loads the configuration of `args`, printing a warning for every key in it that has no effect.
fn load(args: &ConfigArgs) -> Result<Config, Error> {
    load_warning(args).map(|(config, _)| config)
}

/// [`load`], with the warnings it printed.
fn load_warning(args: &ConfigArgs) -> Result<(Config, Vec<String>), Error> {
    let loaded = Config::load_given(args.config.as_deref(), &args.set)?;
    let warnings = warn(loaded.config.ineffective_keys(&loaded.given, config::Use::Run));
    Ok((loaded.config, warnings))
}

/// Prints `warning: …` for each key without effect to stderr; the lines printed.
fn warn(ineffective: Vec<config::Ineffective>) -> Vec<String> {
    ineffective
        .iter()
        .map(|w| {
            let line = format!("warning: {w}");
            eprintln!("{line}");
            line
        })
        .collect()
}

/// Exit code of a run stopped by Ctrl-C or SIGTERM (128 + SIGINT, the shell's convention).
const EXIT_INTERRUPTED: u8 = 130;

/// Sets `stop` on the first Ctrl-C / SIGTERM / SIGHUP (saying `what` happens now); a second one
/// exits at once.
fn install_stop_handler(stop: Arc<AtomicBool>, what: &'static str) {
    let installed = ctrlc::set_handler(move || {
        if stop.swap(true, Ordering::SeqCst) {
            eprintln!("\ninterrupted again: exiting at once (outputs may be incomplete)");
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
        eprintln!("\ninterrupted: {what} (Ctrl-C again: exit at once)");
    });
    if let Err(e) = installed {
        eprintln!("warning: no Ctrl-C handler ({e}); an interrupt will stop the run without finishing its outputs");
    }
}

/// Runs; `Ok(true)` when the run was interrupted.
fn run(args: RunArgs) -> Result<bool, Error> {
    if args.checkpoint_every == Some(0) {
        return Err(Error::Input(
            "--checkpoint-every 0: allowed N >= 1 (steps between checkpoints)".into(),
        ));
    }
    let (config, warnings) = match &args.restart {
        Some(dir) => {
            let file = dir.join(pendulum_fem::commands::run::checkpoint::CHECKPOINT_TOML);
            if !file.is_file() {
                return Err(Error::Input(format!(
                    "run --restart {}: no {} there (a run writes it with --checkpoint-every N)",
                    dir.display(),
                    pendulum_fem::commands::run::checkpoint::CHECKPOINT_TOML
                )));
            }
            // the run wrote checkpoint.toml with every key: only the overrides are the user's
            let config = Config::load(Some(&file), &args.cfg.set)?;
            let given = config::GivenKeys::of_overrides(&args.cfg.set);
            let warnings = warn(config.ineffective_keys(&given, config::Use::Run));
            (config, warnings)
        }
        None => load_warning(&args.cfg)?,
    };
    let stop = Arc::new(AtomicBool::new(false));
    install_stop_handler(
        stop.clone(),
        "stopping after the current step and finishing the outputs",
    );
    let opts = RunOptions {
        config,
        out: args.restart.clone().or_else(|| args.out.clone()),
        force: args.force,
        observers: vec![
            pendulum_fem::render::pictures::attach(),
            pendulum_fem::progress::attach(args.quiet),
        ],
        stop: Some(stop),
        checkpoint_every: args.checkpoint_every,
        restart: args.restart.is_some(),
        warnings,
    };
    let summary = pendulum_fem::commands::run::run(&opts)?;
    if summary.end == RunEnd::Interrupted {
        println!(
            "pendulum-fem run interrupted at t = {} s (step {} of {}); results up to then, plots and viewer in {}",
            summary.time_reached,
            summary.steps,
            pendulum_fem::commands::run::StepPlan::of(&opts.config.time).steps(),
            summary.out_dir.display()
        );
        return Ok(true);
    }
    if !args.quiet {
        pendulum_fem::commands::summary::print_summary(&summary);
    }
    Ok(false)
}

fn init(file: Option<PathBuf>, force: bool) -> Result<(), Error> {
    let path = file.unwrap_or_else(|| PathBuf::from("pendulum.toml"));
    if path.exists() && !force {
        return Err(Error::Config(format!(
            "{} exists; pass --force to overwrite it",
            path.display()
        )));
    }
    std::fs::write(&path, config::commented_default()).map_err(|e| Error::io(&path, e))?;
    println!("wrote {}", path.display());
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let interrupted = |r: Result<bool, Error>| {
        r.map(|i| {
            if i {
                ExitCode::from(EXIT_INTERRUPTED)
            } else {
                ExitCode::SUCCESS
            }
        })
    };
    let result = match cli.command {
        None => interrupted(run(RunArgs::default())),
        Some(Command::Run(args)) => interrupted(run(args)),
        Some(Command::Init { file, force }) => init(file, force).map(|()| ExitCode::SUCCESS),
        Some(Command::Bench(args)) => bench(args).map(|()| ExitCode::SUCCESS),
        Some(Command::Sweep(args)) => sweep(args),
        Some(Command::Modes(args)) => modes(&args).map(|()| ExitCode::SUCCESS),
        Some(Command::Mesh { cfg, out, json }) => load(&cfg)
            .and_then(|c| pendulum_fem::commands::mesh::mesh_command(&c, &out, json))
            .map(|()| ExitCode::SUCCESS),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            // causes that the message above does not already contain
            let mut shown = e.to_string();
            let mut source = std::error::Error::source(&e);
            while let Some(s) = source {
                let m = s.to_string();
                if !shown.contains(&m) {
                    eprintln!("  caused by: {m}");
                    shown.push_str(&m);
                }
                source = s.source();
            }
            ExitCode::FAILURE
        }
    }
}
