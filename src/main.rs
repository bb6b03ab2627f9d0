//! Command-line interface of pendulum-fem: parses arguments, calls the library, prints results and
//! errors. Errors go to stderr with a non-zero exit code.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use clap::{Args, Parser, Subcommand};
use pendulum_fem::commands::run::{RunEnd, RunOptions, RunSummary};
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
    /// Measure speed and memory (see `pendulum-fem bench --help`).
    Bench(BenchArgs),
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
    /// No progress output.
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

#[derive(Args, Debug)]
struct BenchArgs {
    /// What to measure.
    #[arg(value_enum, default_value = "run")]
    what: BenchTarget,
    #[command(flatten)]
    cfg: ConfigArgs,
    /// Repetitions of the default run (`run`); the best is reported.
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
}

fn bench(args: BenchArgs) -> Result<(), Error> {
    use pendulum_fem::commands::bench;
    let config = load(&args.cfg)?;
    match args.what {
        BenchTarget::Run => bench::bench_run(&config, args.repeats, args.ngsolve.as_deref(), &args.anchor),
        BenchTarget::Scaling => bench::bench_scaling(&config, args.steps, args.largest),
        BenchTarget::Memory => bench::bench_memory(&config, 100, 1000),
        BenchTarget::Mesh => pendulum_fem::mesh::bench::bench_mesh(&config, Some(args.triangles)).map(|_| ()),
        BenchTarget::Torque => [0.1, 0.0]
            .into_iter()
            .try_for_each(|m| bench::bench_torque(&config, 100, args.repeats, m).map(|_| ())),
    }
}

fn load(args: &ConfigArgs) -> Result<Config, Error> {
    Config::load(args.config.as_deref(), &args.set)
}

fn print_summary(s: &RunSummary) {
    let deg = |x: f64| x.to_degrees();
    println!("pendulum-fem run finished");
    println!(
        "  mesh               {} triangles, {} nodes, {} unknowns",
        s.mesh_triangles, s.mesh_nodes, s.unknowns
    );
    println!("  steps              {}", s.steps);
    if let Some(last) = s.last_step {
        println!(
            "  time grid          time.end = {} s is not a multiple of time.dt: the last step was shortened to {last:.6e} s to end there",
            s.time_reached
        );
    }
    println!(
        "  Newton iterations  {} ({} cut-backs)",
        s.newton_iterations, s.cutbacks
    );
    println!(
        "  wall time          {:.3} s (mesh {:.3} s, set-up {:.3} s, steps {:.3} s)",
        s.seconds_total, s.seconds_mesh, s.seconds_setup, s.seconds_steps
    );
    println!(
        "  theta              final {:.4} deg, range [{:.4}, {:.4}] deg",
        deg(s.theta_final),
        deg(s.theta_range.0),
        deg(s.theta_range.1)
    );
    match s.period {
        Some(p) => println!("  period estimate    {p:.6} s (zero crossings)"),
        None => println!("  period estimate    - (fewer than two zero crossings)"),
    }
    println!("  max von Mises      {:.4e} Pa", s.von_mises_max);
    println!(
        "  energy error       {:.3e} of the energy scale {:.4e} J (max |energy change - torque work|)",
        s.energy_error, s.energy_scale
    );
    println!("  writing outputs    {:.3} s of the wall time", s.seconds_outputs);
    println!("  results in         {}", s.out_dir.display());
    let (frames, others): (Vec<_>, Vec<_>) = s
        .files
        .iter()
        .partition(|f| f.parent().and_then(|p| p.file_name()).is_some_and(|n| n == "frames"));
    for f in others {
        println!("    {}", f.display());
    }
    if let (Some(first), Some(last)) = (frames.first(), frames.last()) {
        println!(
            "    {} … {} ({} ParaView frames)",
            first.display(),
            last.file_name().unwrap_or_default().to_string_lossy(),
            frames.len()
        );
    }
}

/// Exit code of a run stopped by Ctrl-C or SIGTERM (128 + SIGINT, the shell's convention).
const EXIT_INTERRUPTED: u8 = 130;

/// Sets `stop` on the first Ctrl-C / SIGTERM / SIGHUP; a second one exits at once.
fn install_stop_handler(stop: Arc<AtomicBool>) {
    let installed = ctrlc::set_handler(move || {
        if stop.swap(true, Ordering::SeqCst) {
            eprintln!("\ninterrupted again: exiting at once (outputs may be incomplete)");
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
        eprintln!(
            "\ninterrupted: stopping after the current step and finishing the outputs (Ctrl-C again: exit at once)"
        );
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
    let config = match &args.restart {
        Some(dir) => {
            let file = dir.join(pendulum_fem::commands::run::CHECKPOINT_TOML);
            if !file.is_file() {
                return Err(Error::Input(format!(
                    "run --restart {}: no {} there (a run writes it with --checkpoint-every N)",
                    dir.display(),
                    pendulum_fem::commands::run::CHECKPOINT_TOML
                )));
            }
            Config::load(Some(&file), &args.cfg.set)?
        }
        None => load(&args.cfg)?,
    };
    let stop = Arc::new(AtomicBool::new(false));
    install_stop_handler(stop.clone());
    let opts = RunOptions {
        config,
        out: args.restart.clone().or_else(|| args.out.clone()),
        force: args.force,
        quiet: args.quiet,
        stop: Some(stop),
        checkpoint_every: args.checkpoint_every,
        restart: args.restart.is_some(),
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
    print_summary(&summary);
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
