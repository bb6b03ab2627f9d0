//! Command-line interface of pendulum-fem: parses arguments, calls the library, prints results and
//! errors. Errors go to stderr with a non-zero exit code.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use pendulum_fem::commands::run::{run_with, RunOptions, RunSummary};
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
    /// Override a configuration key, e.g. `--set mesh.max_size=0.01` (repeatable).
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
        "  energy drift       {:.3e} of the largest kinetic energy",
        s.energy_drift
    );
    println!("  results in         {}", s.out_dir.display());
    for f in &s.files {
        println!("    {}", f.display());
    }
}

fn run(args: RunArgs) -> Result<(), Error> {
    let config = load(&args.cfg)?;
    let out_dir = match &args.out {
        Some(dir) => dir.clone(),
        None => config.output.dir.clone(),
    };
    std::fs::create_dir_all(&out_dir).map_err(|e| Error::io(&out_dir, e))?;
    let opts = RunOptions {
        config,
        out: args.out.clone(),
        force: args.force,
        quiet: args.quiet,
    };
    let summary = run_with(&opts, out_dir, |_, _| Ok(()))?;
    print_summary(&summary);
    Ok(())
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
    let result = match cli.command {
        None => run(RunArgs::default()),
        Some(Command::Run(args)) => run(args),
        Some(Command::Init { file, force }) => init(file, force),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            let mut source = std::error::Error::source(&e);
            while let Some(s) = source {
                eprintln!("  caused by: {s}");
                source = s.source();
            }
            ExitCode::FAILURE
        }
    }
}
