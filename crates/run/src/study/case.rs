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

/// Metric columns, after the varied keys.
pub const METRICS: [&str; 9] = [
    "final_time_s",
    "steps",
    "newton_iterations",
    "wall_time_s",
    "theta_min_deg",
    "theta_max_deg",
    "period_s",
    "von_mises_max_Pa",
    "energy_error",
];
/// Metric columns of a study with a wall, after [`METRICS`].
pub const WALL_METRICS: [&str; 2] = ["impacts", "contact_force_max_N"];
/// The last two columns.
pub const STATUS_COLUMNS: [&str; 2] = ["status", "message"];

/// How a case ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CaseStatus {
    /// Reached `time.end`.
    Ok,
    /// Stopped by an error (the configuration, the mesh, the solver, a file); the message and its
    /// causes.
    Failed(String),
    /// Stopped by the stop flag: not finished, to be run again.
    Interrupted,
    /// Not run (yet): a row of the summary for a case without a result.
    Pending,
}

impl CaseStatus {
    /// `ok`, `failed`, `interrupted` or `pending`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Ok => "ok",
            Self::Failed(_) => "failed",
            Self::Interrupted => "interrupted",
            Self::Pending => "pending",
        }
    }

    /// Completed or failed: the case has its row and is not run again by `--resume`.
    pub fn is_finished(&self) -> bool {
        matches!(self, Self::Ok | Self::Failed(_))
    }
}

/// The metrics of a case (`None`: an empty cell).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Metrics {
    /// Time of the last state computed \[s\].
    pub final_time_s: Option<f64>,
    /// Steps computed.
    pub steps: Option<usize>,
    /// Newton iterations over the run.
    pub newton_iterations: Option<usize>,
    /// Wall time of the case (set-up, run and writing) \[s\].
    pub wall_time_s: Option<f64>,
    /// Smallest proxy angle \[deg\].
    pub theta_min_deg: Option<f64>,
    /// Largest proxy angle \[deg\].
    pub theta_max_deg: Option<f64>,
    /// Period from zero crossings \[s\].
    pub period_s: Option<f64>,
    /// Largest von Mises stress \[Pa\].
    pub von_mises_max_pa: Option<f64>,
    /// Energy error of the run (a fraction of its energy scale).
    pub energy_error: Option<f64>,
    /// Impacts and largest contact force; `Some` exactly when a wall is on.
    pub wall: Option<WallMetrics>,
}

/// The metrics of a run with a wall.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WallMetrics {
    /// Impacts over the run.
    pub impacts: Option<f64>,
    /// Largest normal contact force on the head \[N\].
    pub contact_force_max_n: Option<f64>,
}

/// A value of a summary row.
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    /// A number.
    Number(f64),
    /// Text (a varied value, the status, a message).
    Text(String),
    /// Nothing (a metric that does not apply).
    Empty,
}

impl Cell {
    fn of(v: Option<f64>) -> Self {
        v.map_or(Self::Empty, Self::Number)
    }

    /// The CSV field: numbers in the shortest round-trip form, text quoted when it must be.
    pub fn csv(&self) -> String {
        match self {
            Self::Number(v) => number_text(*v),
            Self::Text(s) => csv_field(s),
            Self::Empty => String::new(),
        }
    }
}

/// One row of the summary: the varied values, the metrics and the status.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseRow {
    /// `(key, value as shown)` of each varied key.
    pub varied: Vec<(String, String)>,
    /// The metrics.
    pub metrics: Metrics,
    /// How the case ended.
    pub status: CaseStatus,
}

impl CaseRow {
    /// A row without metrics (a case not run yet, or failed before it started).
    pub fn without_metrics(varied: Vec<(String, String)>, status: CaseStatus) -> Self {
        Self {
            varied,
            metrics: Metrics::default(),
            status,
        }
    }

    /// Whether the row has the wall columns' values (a wall was on).
    pub fn has_wall(&self) -> bool {
        self.metrics.wall.is_some()
    }

    /// The named values in column order; with `wall`, the wall columns too (empty for a row
    /// without a wall).
    pub fn values(&self, wall: bool) -> Vec<(String, Cell)> {
        let m = &self.metrics;
        let mut out: Vec<(String, Cell)> = self
            .varied
            .iter()
            .map(|(k, v)| (k.clone(), Cell::Text(v.clone())))
            .collect();
        let numbers = [
            m.final_time_s,
            m.steps.map(|s| s as f64),
            m.newton_iterations.map(|s| s as f64),
            m.wall_time_s,
            m.theta_min_deg,
            m.theta_max_deg,
            m.period_s,
            m.von_mises_max_pa,
            m.energy_error,
        ];
        out.extend(METRICS.iter().zip(numbers).map(|(n, v)| (n.to_string(), Cell::of(v))));
        if wall {
            let w = m.wall.clone().unwrap_or_default();
            out.push((WALL_METRICS[0].into(), Cell::of(w.impacts)));
            out.push((WALL_METRICS[1].into(), Cell::of(w.contact_force_max_n)));
        }
        let message = match &self.status {
            CaseStatus::Failed(m) => Cell::Text(m.clone()),
            _ => Cell::Empty,
        };
        out.push((STATUS_COLUMNS[0].into(), Cell::Text(self.status.name().into())));
        out.push((STATUS_COLUMNS[1].into(), message));
        out
    }

    /// The CSV line (without the newline) under [`header`]`(keys, wall)`.
    pub fn csv_line(&self, wall: bool) -> String {
        let cells: Vec<String> = self.values(wall).iter().map(|(_, c)| c.csv()).collect();
        cells.join(",")
    }

    /// Reads a row back from a summary line under `header` (columns found by name; the varied
    /// keys are the columns before `final_time_s`).
    pub fn parse(header: &str, line: &str) -> Result<Self, String> {
        let names = split_csv_line(header)?;
        let cells = split_csv_line(line)?;
        if names.len() != cells.len() {
            return Err(format!(
                "{} values, the header has {} columns",
                cells.len(),
                names.len()
            ));
        }
        let first_metric = names
            .iter()
            .position(|n| n == METRICS[0])
            .ok_or_else(|| format!("no column `{}` in the header", METRICS[0]))?;
        let cell = |name: &str| names.iter().position(|n| n == name).map(|i| cells[i].as_str());
        let number = |name: &str| -> Result<Option<f64>, String> {
            match cell(name) {
                None | Some("") => Ok(None),
                Some(text) => text
                    .parse::<f64>()
                    .map(Some)
                    .map_err(|_| format!("`{text}` in column `{name}` is not a number")),
            }
        };
        let count = |name: &str| -> Result<Option<usize>, String> {
            match cell(name) {
                None | Some("") => Ok(None),
                Some(text) => text
                    .parse::<usize>()
                    .map(Some)
                    .map_err(|_| format!("`{text}` in column `{name}` is not a count")),
            }
        };
        let wall = if names.iter().any(|n| n == WALL_METRICS[0]) {
            let w = WallMetrics {
                impacts: number(WALL_METRICS[0])?,
                contact_force_max_n: number(WALL_METRICS[1])?,
            };
            (w != WallMetrics::default()).then_some(w)
        } else {
            None
        };
        let metrics = Metrics {
            final_time_s: number("final_time_s")?,
            steps: count("steps")?,
            newton_iterations: count("newton_iterations")?,
            wall_time_s: number("wall_time_s")?,
            theta_min_deg: number("theta_min_deg")?,
            theta_max_deg: number("theta_max_deg")?,
            period_s: number("period_s")?,
            von_mises_max_pa: number("von_mises_max_Pa")?,
            energy_error: number("energy_error")?,
            wall,
        };
        let message = cell("message").unwrap_or_default().to_string();
        let status = match cell("status") {
            Some("ok") => CaseStatus::Ok,
            Some("failed") => CaseStatus::Failed(message),
            Some("interrupted") => CaseStatus::Interrupted,
            Some("pending") => CaseStatus::Pending,
            other => {
                return Err(format!(
                    "status `{}` is not ok, failed, interrupted or pending",
                    other.unwrap_or("")
                ))
            }
        };
        Ok(Self {
            varied: names[..first_metric]
                .iter()
                .cloned()
                .zip(cells[..first_metric].iter().cloned())
                .collect(),
            metrics,
            status,
        })
    }
}

/// The summary header for the varied `keys`, with the wall columns when `wall`.
pub fn header(keys: &[String], wall: bool) -> String {
    let wall_columns: &[&str] = if wall { &WALL_METRICS } else { &[] };
    let names: Vec<String> = keys
        .iter()
        .map(|k| csv_field(k))
        .chain(
            METRICS
                .iter()
                .chain(wall_columns)
                .chain(&STATUS_COLUMNS)
                .map(|s| s.to_string()),
        )
        .collect();
    names.join(",")
}

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
        crate::files::write_atomically(&path, |w| w.write_all(text.as_bytes()))
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
    crate::files::write_atomically(&dir.join(CASE_SUMMARY), |w| w.write_all(text.as_bytes()))
}

/// A message on one line (a summary row per case).
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// A number in the shortest form that reads back as the same `f64`: integral values as integers
/// (`1000000`, also a TOML integer), others as Rust's shortest round-trip decimal, with an exponent
/// outside `1e-4 ≤ |v| < 1e15` (`1.129941766692634e-10`, not `0.0000000001129941766692634`).
pub fn number_text(v: f64) -> String {
    let a = v.abs();
    if v == v.trunc() && a < 1e15 {
        format!("{}", v as i64)
    } else if (1e-4..1e15).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A CSV field, quoted (RFC 4180) when it holds a comma, a quote, a line break or outer spaces.
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) || s.trim() != s {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Splits one CSV line into its fields (RFC 4180 quoting, no line breaks inside fields).
pub fn split_csv_line(line: &str) -> Result<Vec<String>, String> {
    let mut fields = Vec::new();
    let mut chars = line.chars().peekable();
    loop {
        let mut field = String::new();
        if chars.peek() == Some(&'"') {
            chars.next();
            loop {
                match chars.next() {
                    Some('"') if chars.peek() == Some(&'"') => {
                        chars.next();
                        field.push('"');
                    }
                    Some('"') => break,
                    Some(c) => field.push(c),
                    None => return Err(format!("an unterminated quoted field in `{line}`")),
                }
            }
            match chars.next() {
                None => {
                    fields.push(field);
                    return Ok(fields);
                }
                Some(',') => fields.push(field),
                Some(c) => return Err(format!("`{c}` after a quoted field in `{line}`")),
            }
        } else {
            loop {
                match chars.next() {
                    None => {
                        fields.push(field);
                        return Ok(fields);
                    }
                    Some(',') => break,
                    Some(c) => field.push(c),
                }
            }
            fields.push(field);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_back_as_the_same_value() {
        for v in [
            0.0,
            1.0,
            -3.0,
            2.1e11,
            1e6,
            0.1,
            1.5e-7,
            3e20,
            1.0 / 3.0,
            123456.789,
            f64::NAN,
            f64::INFINITY,
        ] {
            let text = number_text(v);
            let back: f64 = text.parse().unwrap();
            assert!(
                back.to_bits() == v.to_bits() || (v.is_nan() && back.is_nan()),
                "{v} -> {text}"
            );
        }
        assert_eq!(number_text(1.129941766692634e-10), "1.129941766692634e-10");
        assert_eq!(number_text(74449.79587866667), "74449.79587866667");
    }

    #[test]
    fn rows_read_back_as_written() {
        let row = CaseRow {
            varied: vec![
                ("material.youngs_modulus".into(), "2.1e11".into()),
                ("material.model".into(), "neo-hookean".into()),
            ],
            metrics: Metrics {
                final_time_s: Some(0.1),
                steps: Some(10),
                newton_iterations: Some(31),
                wall_time_s: Some(0.123456789),
                theta_min_deg: Some(17.123456789012345),
                theta_max_deg: Some(20.0),
                period_s: None,
                von_mises_max_pa: Some(1.2345e5),
                energy_error: Some(1.0 / 3.0),
                wall: None,
            },
            status: CaseStatus::Ok,
        };
        let keys: Vec<String> = row.varied.iter().map(|(k, _)| k.clone()).collect();
        for wall in [false, true] {
            let back = CaseRow::parse(&header(&keys, wall), &row.csv_line(wall)).unwrap();
            assert_eq!(back, row);
        }
        let failed = CaseRow {
            status: CaseStatus::Failed("time step 1 failed: \"x\", y".into()),
            metrics: Metrics {
                wall: Some(WallMetrics {
                    impacts: Some(2.0),
                    contact_force_max_n: None,
                }),
                ..Default::default()
            },
            ..row
        };
        let line = failed.csv_line(true);
        assert!(line.ends_with(",failed,\"time step 1 failed: \"\"x\"\", y\""), "{line}");
        assert_eq!(CaseRow::parse(&header(&keys, true), &line).unwrap(), failed);
        assert!(CaseRow::parse(&header(&keys, false), "1,2").is_err());
    }
}
