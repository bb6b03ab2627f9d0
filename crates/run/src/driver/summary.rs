//! The figures of a finished run ([`RunSummary`]) and how it ended ([`RunEnd`]).

use std::path::PathBuf;

use pendulum_fem_core::post::PeriodEstimator;
use pendulum_fem_core::simulation::{ContactEvent, StepRecord};

use crate::impacts::ImpactSummary;

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
    /// not a multiple of `time.dt` (see [`pendulum_fem_core::config::StepPlan`]).
    pub last_step: Option<f64>,
    /// Newton iterations (linear solves) over all steps.
    pub newton_iterations: usize,
    /// Numeric factorisations over the run.
    pub factorizations: usize,
    /// Step cut-backs.
    pub cutbacks: usize,
    /// Warnings of the run: those about its configuration ([`super::RunOptions::warnings`]), then
    /// those it raised (each also printed to stderr when raised): the reduced body's when it does
    /// not apply ([`pendulum_fem_core::reduced::validity`]).
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
    /// [`crate::audit::EnergyAudit`]).
    pub energy_error: f64,
    /// The energy scale of the run \[J\] (see [`crate::audit::EnergyAudit`]).
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

impl RunSummary {
    /// Takes a record into the run's figures: θ's range and last value, the period, the largest
    /// von Mises stress and, with a wall, the impacts and the largest contact force (the record's
    /// and the peaks between the records, in `events`, the contact events up to the record). The
    /// one tally for a run's records and a restarted run's records before its checkpoint.
    pub(super) fn take_record(
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
    /// Stopped at a step boundary because [`super::RunOptions::stop`] was set (Ctrl-C, SIGTERM).
    Interrupted,
}
