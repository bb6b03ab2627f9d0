//! One case of a parameter study: run a resolved configuration in its own folder and reduce the
//! run to one row of the study's `summary.csv`.
//!
//! Library items only (the configuration, the run driver, the writers): no command-line parsing,
//! no progress bars, no signal handling, so that the local sweep, job-array tasks and the Python
//! package (a Dask worker) all produce the same row for the same case.
//!
//! A case folder holds, when the case has finished (completed or failed):
//!
//! - [`CASE_CONFIG`]: the resolved configuration (input file paths made absolute), absent when the
//!   configuration itself was the error;
//! - `results.csv` and `status.json` of the run (and the other outputs the configuration asks
//!   for);
//! - [`CASE_SUMMARY`]: the header and this case's row of the study's summary, written last
//!   (atomically): its presence marks a finished case.
//!
//! A case stopped by the stop flag (Ctrl-C) is not finished: it writes no [`CASE_SUMMARY`] and
//! is run again by `sweep --resume`.
//!
//! ## Columns
//!
//! The varied keys (values as given), then [`METRICS`]: final time \[s\], steps, Newton
//! iterations, wall time \[s\], smallest and largest θ \[deg\], period \[s\] (empty when θ crossed
//! zero fewer than twice, or when the head struck a wall: θ then crosses zero inside the impacts), largest von Mises stress \[Pa\], energy error (see
//! [`crate::audit::EnergyAudit`]); then [`WALL_METRICS`] (number of impacts, largest
//! contact force \[N\]) when a wall is on (`wall.kind` other than `"none"`); then `status`
//! (`ok`, `failed`, `interrupted`, `pending`) and `message` (the error of a failed case). A
//! failed case keeps the final time and the steps it reached; its other metrics are empty.
//! Numbers are written in Rust's shortest round-trip form, so a value read back is bit-identical.

mod row;

pub use row::{
    csv_field, header, number_text, split_csv_line, CaseRow, CaseStatus, Cell, Metrics, WallMetrics, METRICS,
    STATUS_COLUMNS, WALL_METRICS,
};

use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Instant;

use crate::driver::{Attach, RunEnd, RunOptions, RunSummary};
use crate::status::{error_chain, RunStatus, STATUS_JSON};
use crate::{Config, Error};

/// This case's row of the study's summary, in the case folder.
pub const CASE_SUMMARY: &str = "summary.csv";
/// The resolved configuration of the case, in the case folder.
pub const CASE_CONFIG: &str = "config.toml";

/// What a case needs besides its configuration.
#[derive(Clone, Debug, Default)]
pub struct CaseOptions {
    /// Threads of the case's own rayon pool (the element loops and, for large meshes, the sparse
    /// factorisation run on it); 0: the global pool (all cores). A sweep runs several cases at
    /// once with 1 each.
    pub threads: usize,
    /// When set, the run stops at the next step boundary and the case is
    /// [`CaseStatus::Interrupted`] (no row is written).
    pub stop: Option<Arc<AtomicBool>>,
    /// What watches each case's run (the CLI attaches the pictures, which a case draws when its
    /// configuration keeps them, see [`lean_outputs`]); none: the case writes its CSV files only.
    pub observers: Vec<Attach>,
}

/// Switches off the outputs a case does not need by default (plots, animations, ParaView frames,
/// viewer): a case writes `results.csv`, `status.json` and its summary row only.
pub fn lean_outputs(cfg: &mut Config) {
    let o = &mut cfg.output;
    o.plots = false;
    o.animation = false;
    o.paraview = false;
    o.viewer = false;
}

/// Runs the case in `dir` (created if needed; the outputs of an earlier attempt are removed first)
/// and returns its row; unless interrupted, also writes [`CASE_CONFIG`] and [`CASE_SUMMARY`]. Never
/// fails: an invalid configuration (`config` an error), a run that fails and a folder that cannot
/// be written all give a [`CaseStatus::Failed`] row with the message.
pub fn run_case(
    varied: Vec<(String, String)>,
    config: Result<Config, Error>,
    dir: &Path,
    opts: &CaseOptions,
) -> CaseRow {
    let start = Instant::now();
    let mut row = match prepare(dir) {
        Err(e) => CaseRow::without_metrics(varied, CaseStatus::Failed(one_line(&error_chain(&e)))),
        Ok(()) => match config {
            Err(e) => CaseRow::without_metrics(varied, CaseStatus::Failed(one_line(&error_chain(&e)))),
            Ok(cfg) => run_config(varied, cfg, dir, opts),
        },
    };
    row.metrics.wall_time_s = Some(start.elapsed().as_secs_f64());
    if row.status.is_finished() {
        if let Err(e) = write_row(dir, &row) {
            row.status = CaseStatus::Failed(one_line(&error_chain(&e)));
        }
    }
    row
}

/// [`run_case`] with the configuration as TOML text (a resolved `config.toml`).
pub fn run_case_toml(varied: Vec<(String, String)>, toml_text: &str, dir: &Path, opts: &CaseOptions) -> CaseRow {
    run_case(varied, Config::from_toml_str(toml_text), dir, opts)
}

/// The row of a finished case in `dir` (from its [`CASE_SUMMARY`]); `None` when there is none.
pub fn read_row(dir: &Path) -> Result<Option<CaseRow>, Error> {
    let path = dir.join(CASE_SUMMARY);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(Error::io(&path, e)),
    };
    let mut lines = text.lines();
    let (Some(head), Some(line)) = (lines.next(), lines.next()) else {
        return Err(Error::Input(format!(
            "{}: expected a header and one row",
            path.display()
        )));
    };
    CaseRow::parse(head, line)
        .map(Some)
        .map_err(|m| Error::Input(format!("{}: {m}", path.display())))
}

/// The resolved configuration as written to [`CASE_CONFIG`] (input file paths made absolute, so
/// that it reads back from any folder).
pub fn config_text(cfg: &Config) -> Result<String, Error> {
    crate::files::portable_toml(cfg, CASE_CONFIG)
}

/// Creates `dir` and removes what an earlier attempt of the case wrote there.
fn prepare(dir: &Path) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    for name in [CASE_SUMMARY, CASE_CONFIG] {
        let path = dir.join(name);
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(Error::io(&path, e)),
            _ => {}
        }
    }
    crate::outdir::clear_run_outputs(dir)
}

fn run_config(varied: Vec<(String, String)>, cfg: Config, dir: &Path, opts: &CaseOptions) -> CaseRow {
    let wall = cfg.wall.is_present();
    let written = config_text(&cfg).and_then(|text| {
        let path = dir.join(CASE_CONFIG);
        pendulum_fem_core::store::write_atomically(&path, |w| w.write_all(text.as_bytes()))
    });
    if let Err(e) = written {
        return CaseRow::without_metrics(varied, CaseStatus::Failed(one_line(&error_chain(&e))));
    }
    let run_opts = RunOptions {
        config: cfg,
        out: Some(dir.to_path_buf()),
        force: true,
        stop: opts.stop.clone(),
        observers: opts.observers.clone(),
        ..Default::default()
    };
    // a panic in one case (a bug) is that case's failure, not the end of the study
    let run = || {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| crate::driver::run(&run_opts))).unwrap_or_else(
            |panic| {
                let what = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_default();
                Err(Error::Input(format!("the run panicked: {what}")))
            },
        )
    };
    let result = match opts.threads {
        0 => run(),
        n => match rayon::ThreadPoolBuilder::new().num_threads(n).build() {
            Ok(pool) => pool.install(run),
            Err(e) => Err(Error::Input(format!("a thread pool of {n} threads: {e}"))),
        },
    };
    match result {
        Ok(s) if s.end == RunEnd::Interrupted => CaseRow::without_metrics(varied, CaseStatus::Interrupted),
        Ok(s) => CaseRow {
            varied,
            metrics: metrics_of(&s, wall.then(|| wall_metrics(&s))),
            status: CaseStatus::Ok,
        },
        Err(e) => {
            // the steps and time reached are in status.json (written by the run however it ended)
            let reached = RunStatus::read(&dir.join(STATUS_JSON)).ok();
            let mut row = CaseRow::without_metrics(varied, CaseStatus::Failed(one_line(&error_chain(&e))));
            row.metrics.final_time_s = reached.as_ref().and_then(|r| r.time_s);
            row.metrics.steps = reached.as_ref().and_then(|r| r.step);
            row
        }
    }
}

/// The metrics of a completed run (the wall time is the case's, set by [`run_case`]).
pub fn metrics_of(s: &RunSummary, wall: Option<WallMetrics>) -> Metrics {
    Metrics {
        final_time_s: Some(s.time_reached),
        steps: Some(s.steps),
        newton_iterations: Some(s.newton_iterations),
        wall_time_s: Some(s.seconds_total),
        theta_min_deg: Some(s.theta_range.0.to_degrees()),
        theta_max_deg: Some(s.theta_range.1.to_degrees()),
        period_s: s.period,
        von_mises_max_pa: Some(s.von_mises_max),
        energy_error: Some(s.energy_error),
        wall,
    }
}

/// Impacts and the largest contact force of a run with a wall, from its summary
/// ([`RunSummary::contact`]: the records and the events' peak forces between them).
fn wall_metrics(s: &RunSummary) -> WallMetrics {
    WallMetrics {
        impacts: s.contact.map(|(n, _)| n as f64),
        contact_force_max_n: s.contact.map(|(_, f)| f),
    }
}

/// Writes the case's [`CASE_SUMMARY`] (atomically).
fn write_row(dir: &Path, row: &CaseRow) -> Result<(), Error> {
    let keys: Vec<String> = row.varied.iter().map(|(k, _)| k.clone()).collect();
    let text = format!("{}\n{}\n", header(&keys, row.has_wall()), row.csv_line(row.has_wall()));
    pendulum_fem_core::store::write_atomically(&dir.join(CASE_SUMMARY), |w| w.write_all(text.as_bytes()))
}

/// A message on one line (a summary row per case).
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
