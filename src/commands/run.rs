//! `pendulum-fem run`: mesh, simulate, stream `results.csv`, summarise.

use std::path::PathBuf;
use std::time::Instant;

use crate::io::csv::CsvWriter;
use crate::post::PeriodEstimator;
use crate::simulation::{Simulation, StepRecord};
use crate::{mesh, Config, Error};

/// What to run and where to write.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// The configuration (already validated).
    pub config: Config,
    /// Output folder; `None`: a fresh folder under `output.dir`.
    pub out: Option<PathBuf>,
    /// Allow writing into an existing non-empty `out`.
    pub force: bool,
    /// No progress output.
    pub quiet: bool,
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
    /// Steps computed.
    pub steps: usize,
    /// Newton iterations (linear solves) over all steps.
    pub newton_iterations: usize,
    /// Step cut-backs.
    pub cutbacks: usize,
    /// Final proxy angle \[rad\].
    pub theta_final: f64,
    /// Smallest and largest proxy angle \[rad\].
    pub theta_range: (f64, f64),
    /// Period from zero crossings \[s\].
    pub period: Option<f64>,
    /// Largest von Mises stress over the run \[Pa\].
    pub von_mises_max: f64,
    /// Largest |E(t) − E(0)| divided by the largest kinetic energy.
    pub energy_drift: f64,
    /// Wall time: meshing \[s\].
    pub seconds_mesh: f64,
    /// Wall time: set-up (operators, symbolic factorisation) \[s\].
    pub seconds_setup: f64,
    /// Wall time: time stepping including post-processing and writing \[s\].
    pub seconds_steps: f64,
    /// Wall time in total \[s\].
    pub seconds_total: f64,
    /// Solver timings.
    pub timings: crate::newton::Timings,
}

/// The values of a record in CSV column order.
pub fn csv_values(r: &StepRecord) -> Vec<f64> {
    vec![
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
    ]
}

/// Runs the simulation described by `opts`, calling `observe` after every record (step 0
/// included) with the simulation and the record.
pub fn run_with(
    opts: &RunOptions,
    out_dir: PathBuf,
    mut observe: impl FnMut(&Simulation, &StepRecord) -> Result<(), Error>,
) -> Result<RunSummary, Error> {
    let start = Instant::now();
    let cfg = &opts.config;
    let mesh = mesh::generate(cfg)?;
    let seconds_mesh = start.elapsed().as_secs_f64();
    let t_setup = Instant::now();
    let mut sim = Simulation::from_config(cfg, mesh)?;
    let seconds_setup = t_setup.elapsed().as_secs_f64();
    let t_steps = Instant::now();
    let csv_path = out_dir.join("results.csv");
    let mut csv = CsvWriter::create(&csv_path, StepRecord::HEADER)?;
    let mut summary = RunSummary {
        out_dir: out_dir.clone(),
        mesh_triangles: sim.model.mesh.triangles.len(),
        mesh_nodes: sim.model.mesh.num_nodes(),
        unknowns: 2 * sim.model.mesh.num_nodes() + 2,
        theta_range: (f64::INFINITY, f64::NEG_INFINITY),
        ..Default::default()
    };
    let mut period = PeriodEstimator::default();
    let (mut e0, mut kin_max, mut drift) = (None, 0.0f64, 0.0f64);
    let steps = cfg.time.steps();
    let mut record = sim.record(0);
    loop {
        csv.row(&csv_values(&record))?;
        observe(&sim, &record)?;
        period.push(record.time, record.theta);
        summary.theta_range.0 = summary.theta_range.0.min(record.theta);
        summary.theta_range.1 = summary.theta_range.1.max(record.theta);
        summary.von_mises_max = summary.von_mises_max.max(record.von_mises_max);
        let e_ref = *e0.get_or_insert(record.total);
        kin_max = kin_max.max(record.kinetic);
        drift = drift.max((record.total - e_ref).abs());
        summary.theta_final = record.theta;
        if sim.step >= steps {
            break;
        }
        record = sim.advance()?;
    }
    summary.files.push(csv.finish()?);
    summary.steps = sim.step;
    summary.newton_iterations = sim.total_iterations;
    summary.cutbacks = sim.cutbacks;
    summary.period = period.period();
    summary.energy_drift = if kin_max > 0.0 { drift / kin_max } else { 0.0 };
    summary.timings = sim.timings();
    summary.seconds_mesh = seconds_mesh;
    summary.seconds_setup = seconds_setup;
    summary.seconds_steps = t_steps.elapsed().as_secs_f64();
    summary.seconds_total = start.elapsed().as_secs_f64();
    Ok(summary)
}
