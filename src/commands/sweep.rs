//! `pendulum-fem sweep`: a parameter study, one run per case, locally in parallel or as the tasks
//! of a cluster job array.
//!
//! The cases come from `--vary KEY=VALUES` arguments and sweep files ([`grid`]); each runs in its
//! own folder `DIR/case-NNNN/` ([`case`]), and `DIR/summary.csv` has one row per case, in case
//! order. `DIR/cases.csv` lists the cases (number and the value of each varied key), written
//! before any case runs; job-array tasks and `--gather` read it.
//!
//! - **Local**: [`run_sweep`] runs the cases on `jobs` worker threads, each case on a rayon pool
//!   of its own (1 thread by default: a case is small, and cases are many). A failed case never
//!   stops the others. The stop flag (Ctrl-C) stops the running cases at their next step
//!   boundary and starts no new one; the summary then lists the finished cases and the others as
//!   `pending`, and `--resume` runs only those.
//! - **Job arrays**: [`run_case_index`] runs one case (`--case-index K` or the scheduler's array
//!   index) into the shared `DIR`; [`gather`] builds `summary.csv` from the case folders.
//!
//! `summary.csv` is rewritten (atomically) at most every two seconds while cases finish and once
//! at the end, so that it is always a consistent table; the figures `summary_<key>.png` (every
//! metric against each numeric varied key) are drawn at the end.

/// One case and its summary row (in `pendulum-fem-run`, shared with the Python package).
pub use pendulum_fem_run::study::case;
/// The grid of cases (in `pendulum-fem-run`).
pub use pendulum_fem_run::study::grid;
mod plots;
mod progress;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

pub use case::{CaseOptions, CaseRow, CaseStatus};
pub use grid::Plan;

use crate::{Config, Error};
use progress::SweepProgress;

/// The study's summary, one row per case.
pub const SUMMARY_CSV: &str = "summary.csv";
/// The list of cases (`case,<keys…>`, values as TOML literals).
pub const CASES_CSV: &str = "cases.csv";

/// The folder of case `k`: `out/case-NNNN`.
pub fn case_dir(out: &Path, k: usize) -> PathBuf {
    out.join(format!("case-{k:04}"))
}

/// A study: the base configuration, overrides for every case, and the cases.
#[derive(Clone, Debug, PartialEq)]
pub struct Sweep {
    /// Base configuration file (`None`: the defaults).
    pub base: Option<PathBuf>,
    /// Overrides for every case (a sweep file's `set`, then `--set`).
    pub set: Vec<String>,
    /// The cases.
    pub plan: Plan,
    /// Keep the configuration's plots, animations, ParaView frames and viewer in every case
    /// (default: only `results.csv`, see [`case::lean_outputs`]).
    pub all_outputs: bool,
}

impl Sweep {
    /// The study of a command line: `--config`, `--set`, `--vary`, `--zip` and `--file`. A
    /// `--config` takes the place of the file's `config`; `--set` comes after the file's `set`;
    /// the file's plans come before the `--vary` ones. Keys that are no configuration keys are an
    /// error here, before anything runs.
    pub fn new(
        config: Option<PathBuf>,
        set: Vec<String>,
        vary: &[String],
        zip: bool,
        file: Option<&Path>,
    ) -> Result<Self, Error> {
        let (mut base, mut sets, mut zip, mut plans) = (config, Vec::new(), zip, Vec::new());
        if let Some(f) = file {
            let sf = grid::read_sweep_file(f)?;
            base = base.or(sf.config);
            sets = sf.set;
            zip |= sf.zip;
            plans = sf.plans;
        }
        sets.extend(set);
        for v in vary {
            plans.push(grid::parse_vary(v)?);
        }
        let mut plan = Plan::unit();
        for p in plans {
            plan = if zip { plan.zip(p)? } else { plan.product(p)? };
        }
        if plan.keys.is_empty() {
            return Err(Error::Config(format!(
                "sweep: nothing to vary; give --vary KEY=VALUES (VALUES {}) or --file with [vary] or [[case]]",
                grid::VALUE_FORMS
            )));
        }
        let sweep = Self {
            base,
            set: sets,
            plan,
            all_outputs: false,
        };
        sweep.check()?;
        Ok(sweep)
    }

    /// Number of cases.
    pub fn len(&self) -> usize {
        self.plan.len()
    }

    /// Whether there are no cases.
    pub fn is_empty(&self) -> bool {
        self.plan.is_empty()
    }

    /// The configuration of case `k`: the base, every `set`, the case's values; lean outputs unless
    /// [`Sweep::all_outputs`].
    pub fn config(&self, k: usize) -> Result<Config, Error> {
        let mut overrides = self.set.clone();
        overrides.extend(self.plan.overrides(k));
        let mut cfg = Config::load(self.base.as_deref(), &overrides)?;
        if !self.all_outputs {
            case::lean_outputs(&mut cfg);
        }
        Ok(cfg)
    }

    /// The keys of the base, `--set` and the cases that have no effect in a case's configuration
    /// ([`Config::ineffective_keys`]), each once: as the first case that has it says it, with the
    /// share of the cases that have it when not all do.
    pub fn ineffective_keys(&self) -> Vec<String> {
        let mut found: Vec<(String, String, usize)> = Vec::new();
        for k in 0..self.len() {
            let mut overrides = self.set.clone();
            overrides.extend(self.plan.overrides(k));
            // a case whose configuration is wrong fails with its own message
            let Ok(loaded) = Config::load_given(self.base.as_deref(), &overrides) else {
                continue;
            };
            for w in loaded.config.ineffective_keys(&loaded.given, crate::config::Use::Run) {
                match found.iter_mut().find(|(key, _, _)| key == w.key) {
                    Some((_, _, cases)) => *cases += 1,
                    None => found.push((w.key.to_string(), w.to_string(), 1)),
                }
            }
        }
        found
            .into_iter()
            .map(|(_, text, cases)| match cases == self.len() {
                true => text,
                false => format!("{text} (in {cases} of {} cases)", self.len()),
            })
            .collect()
    }

    /// The text of [`CASES_CSV`].
    pub fn cases_csv(&self) -> String {
        self.plan.to_cases_csv()
    }

    /// Fails early on what would fail every case alike: an unreadable base file, and keys that are
    /// no configuration keys (in `--vary`, the sweep file or `--set`). Values out of range are left
    /// to the cases (a case with a bad value is a failed row, the others run).
    fn check(&self) -> Result<(), Error> {
        if let Some(base) = &self.base {
            let text = std::fs::read_to_string(base).map_err(|e| {
                Error::Config(format!(
                    "sweep: cannot read the base configuration {}: {e}",
                    base.display()
                ))
            })?;
            text.parse::<toml::Table>()
                .map_err(|e| Error::Config(format!("sweep: the base configuration {}: {e}", base.display())))?;
        }
        let not_a_key = |e: &Error| {
            let m = e.to_string();
            crate::config::reports_an_unknown_key(&m)
                || m.contains("is a value, not a section")
                || m.contains("must be section.name")
        };
        for (j, key) in self.plan.keys.iter().enumerate() {
            let Some(value) = self.plan.cases.iter().find_map(|c| c[j].clone()) else {
                continue;
            };
            let mut overrides = self.set.clone();
            overrides.push(format!("{key}={value}"));
            if let Err(e) = Config::load(self.base.as_deref(), &overrides) {
                if not_a_key(&e) {
                    return Err(Error::Config(format!("sweep: {key} is not a configuration key ({e})")));
                }
            }
        }
        match Config::load(self.base.as_deref(), &self.set) {
            Err(e) if not_a_key(&e) => Err(e),
            _ => Ok(()),
        }
    }
}

/// How a sweep runs.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// The sweep folder.
    pub out: PathBuf,
    /// Cases run at once; 0: the number of cores.
    pub jobs: usize,
    /// Threads per case (see [`CaseOptions::threads`]); 1 by default.
    pub threads: usize,
    /// Continue the sweep in `out`: finished cases are kept, the others run.
    pub resume: bool,
    /// No progress output.
    pub quiet: bool,
    /// Draw `summary_<key>.png`.
    pub plots: bool,
    /// Stop flag (Ctrl-C): running cases stop at their next step, no new case starts.
    pub stop: Option<Arc<AtomicBool>>,
}

impl Default for SweepOptions {
    fn default() -> Self {
        Self {
            out: PathBuf::from("sweep"),
            jobs: 0,
            threads: 1,
            resume: false,
            quiet: false,
            plots: true,
            stop: None,
        }
    }
}

/// What a sweep (or a gather) did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SweepReport {
    /// The sweep folder.
    pub out: PathBuf,
    /// Cases in the study.
    pub cases: usize,
    /// Cases run now.
    pub ran: usize,
    /// Cases finished before (`--resume`) and kept.
    pub skipped: usize,
    /// Cases that completed.
    pub ok: usize,
    /// Cases that failed.
    pub failed: Vec<usize>,
    /// Cases without a result (interrupted, or a job-array task that did not run).
    pub pending: Vec<usize>,
    /// Whether the stop flag ended the sweep.
    pub interrupted: bool,
    /// `summary.csv`.
    pub summary: PathBuf,
    /// The figures written.
    pub plots: Vec<PathBuf>,
    /// Wall time of the sweep \[s\].
    pub seconds: f64,
    /// Worker threads used.
    pub jobs: usize,
}

/// Prepares the sweep folder: creates it and writes [`CASES_CSV`], or, for a folder that holds
/// this study already, checks that the case list is the same. `shared`: a job-array task, for
/// which the folder of the same study is expected; otherwise a folder with a study needs
/// `resume`, and a non-empty folder without one is refused.
fn prepare_dir(sweep: &Sweep, out: &Path, resume: bool, shared: bool) -> Result<(), Error> {
    let cases = out.join(CASES_CSV);
    let text = sweep.cases_csv();
    match std::fs::read_to_string(&cases) {
        Ok(existing) if existing == text => {
            if !(resume || shared) {
                return Err(Error::Config(format!(
                    "sweep --out {}: the folder holds this sweep already; pass --resume to continue it \
                     (finished cases are kept), or choose another --out",
                    out.display()
                )));
            }
            Ok(())
        }
        Ok(_) => Err(Error::Config(format!(
            "sweep --out {}: the folder holds another sweep ({CASES_CSV} lists other cases); choose another --out",
            out.display()
        ))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let non_empty = std::fs::read_dir(out).is_ok_and(|mut d| d.next().is_some());
            if non_empty && !shared {
                return Err(Error::Config(format!(
                    "sweep --out {}: the folder is not empty and holds no sweep; choose another --out",
                    out.display()
                )));
            }
            std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
            // job-array tasks starting together all write it (the same text): each through a
            // temporary file of its own, renamed into place
            crate::store::write_bytes_atomically(&cases, text.as_bytes())
        }
        Err(e) => Err(Error::io(&cases, e)),
    }
}

/// The row of case `k` if it finished earlier, after checking that it was run with the case's
/// configuration (the same values and, when it had one, the same resolved `config.toml`).
fn finished_row(sweep: &Sweep, out: &Path, k: usize) -> Result<Option<CaseRow>, Error> {
    let dir = case_dir(out, k);
    let Some(row) = case::read_row(&dir)? else {
        return Ok(None);
    };
    if !row.status.is_finished() {
        return Ok(None);
    }
    let stale = |what: &str| {
        Error::Config(format!(
            "sweep --resume: {} was run with {what} than this sweep gives it (the base configuration or --set \
             changed?); choose another --out, or remove the case folder to run it again",
            dir.display()
        ))
    };
    if row.varied != sweep.plan.shown(k) {
        return Err(stale("other values"));
    }
    // the outputs asked for ([output]) may change; everything that changes the results may not
    let stored = dir.join(case::CASE_CONFIG);
    if let (Ok(text), Ok(cfg)) = (std::fs::read_to_string(&stored), sweep.config(k)) {
        let same = Config::from_toml_str(&text).is_ok_and(|mut old| {
            old.output = cfg.output.clone();
            case::config_text(&old).ok() == case::config_text(&cfg).ok()
        });
        if !same {
            return Err(stale("another configuration"));
        }
    }
    Ok(Some(row))
}

/// Runs every case of `sweep` into `opts.out` (see the module documentation) and writes the
/// summary and its figures. Failed cases are in the report, not an error; errors are about the
/// sweep folder itself.
pub fn run_sweep(sweep: &Sweep, opts: &SweepOptions) -> Result<SweepReport, Error> {
    let start = Instant::now();
    prepare_dir(sweep, &opts.out, opts.resume, false)?;
    let n = sweep.len();
    let mut rows: Vec<Option<CaseRow>> = vec![None; n];
    let mut todo = Vec::new();
    for (k, row) in rows.iter_mut().enumerate() {
        if opts.resume {
            *row = finished_row(sweep, &opts.out, k)?;
        }
        if row.is_none() {
            todo.push(k);
        }
    }
    let skipped = n - todo.len();
    let jobs = match opts.jobs {
        0 => std::thread::available_parallelism().map_or(1, |p| p.get()),
        j => j,
    }
    .min(todo.len())
    .max(1);
    let progress = Mutex::new(SweepProgress::new(n, skipped, opts.quiet));
    let state = Mutex::new(State {
        rows,
        last_write: Instant::now(),
    });
    let next = AtomicUsize::new(0);
    let stopped = || opts.stop.as_ref().is_some_and(|s| s.load(Ordering::SeqCst));
    let case_opts = CaseOptions {
        threads: opts.threads,
        stop: opts.stop.clone(),
        // a case draws the pictures its configuration keeps (`--all-outputs`)
        observers: vec![crate::render::pictures::attach()],
    };
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| loop {
                if stopped() {
                    break;
                }
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(&k) = todo.get(i) else { break };
                let row = case::run_case(
                    sweep.plan.shown(k),
                    sweep.config(k),
                    &case_dir(&opts.out, k),
                    &case_opts,
                );
                progress.lock().expect("progress").case_done(k, &row);
                if row.status.is_finished() {
                    let mut s = state.lock().expect("sweep state");
                    s.rows[k] = Some(row);
                    if s.last_write.elapsed() > Duration::from_secs(2) {
                        // best effort: the final write below reports a failure
                        let _ = write_summary(&opts.out, sweep, &s.rows);
                        s.last_write = Instant::now();
                    }
                }
            });
        }
    });
    progress.into_inner().expect("progress").finish();
    let state = state.into_inner().expect("sweep state");
    let summary = write_summary(&opts.out, sweep, &state.rows)?;
    let rows = full_rows(sweep, &state.rows);
    let plots = match opts.plots {
        true => plots::write_plots(&opts.out, &sweep.plan.keys, &rows)?,
        false => Vec::new(),
    };
    let mut report = report_of(&opts.out, &rows, summary, plots);
    report.skipped = skipped;
    report.ran = todo.len() - report.pending.len();
    report.interrupted = stopped() && !report.pending.is_empty();
    report.seconds = start.elapsed().as_secs_f64();
    report.jobs = jobs;
    Ok(report)
}

/// The rows so far and when the summary was last written.
struct State {
    rows: Vec<Option<CaseRow>>,
    last_write: Instant,
}

/// Every case's row: the finished ones, `pending` for the others.
fn full_rows(sweep: &Sweep, rows: &[Option<CaseRow>]) -> Vec<CaseRow> {
    rows.iter()
        .enumerate()
        .map(|(k, r)| {
            r.clone()
                .unwrap_or_else(|| CaseRow::without_metrics(sweep.plan.shown(k), CaseStatus::Pending))
        })
        .collect()
}

/// Writes `out/summary.csv` (atomically): every case in order; the wall columns when any case has
/// a wall.
fn write_summary(out: &Path, sweep: &Sweep, rows: &[Option<CaseRow>]) -> Result<PathBuf, Error> {
    write_rows(out, &sweep.plan.keys, &full_rows(sweep, rows))
}

fn write_rows(out: &Path, keys: &[String], rows: &[CaseRow]) -> Result<PathBuf, Error> {
    let wall = rows.iter().any(CaseRow::has_wall);
    let mut text = case::header(keys, wall);
    text.push('\n');
    for row in rows {
        text.push_str(&row.csv_line(wall));
        text.push('\n');
    }
    let path = out.join(SUMMARY_CSV);
    crate::store::write_atomically(&path, |w| w.write_all(text.as_bytes()))?;
    Ok(path)
}

fn report_of(out: &Path, rows: &[CaseRow], summary: PathBuf, plots: Vec<PathBuf>) -> SweepReport {
    let with = |f: fn(&CaseStatus) -> bool| {
        rows.iter()
            .enumerate()
            .filter(move |(_, r)| f(&r.status))
            .map(|(k, _)| k)
    };
    SweepReport {
        out: out.to_path_buf(),
        cases: rows.len(),
        ok: with(|s| *s == CaseStatus::Ok).count(),
        failed: with(|s| matches!(s, CaseStatus::Failed(_))).collect(),
        pending: with(|s| !s.is_finished()).collect(),
        summary,
        plots,
        ..Default::default()
    }
}

/// Runs case `k` of `sweep` alone into `out` (a job-array task): the folder may already hold the
/// study (other tasks write there too); with `resume`, a finished case is not run again. Writes
/// no `summary.csv` (see [`gather`]).
pub fn run_case_index(sweep: &Sweep, out: &Path, k: usize, resume: bool, opts: &CaseOptions) -> Result<CaseRow, Error> {
    let n = sweep.len();
    if k >= n {
        return Err(Error::Config(format!(
            "sweep --case-index {k}: out of range; this sweep has {n} cases, numbered 0 to {} (`sweep --list` \
             prints the count)",
            n - 1
        )));
    }
    prepare_dir(sweep, out, resume, true)?;
    if resume {
        if let Some(row) = finished_row(sweep, out, k)? {
            return Ok(row);
        }
    }
    Ok(case::run_case(
        sweep.plan.shown(k),
        sweep.config(k),
        &case_dir(out, k),
        opts,
    ))
}

/// Builds `dir/summary.csv` (and with `plots` the figures) from the case folders of the sweep in
/// `dir` (its [`CASES_CSV`] says which cases there are): cases without a result are `pending`.
pub fn gather(dir: &Path, plots: bool) -> Result<SweepReport, Error> {
    let start = Instant::now();
    let path = dir.join(CASES_CSV);
    let text = std::fs::read_to_string(&path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => Error::Config(format!(
            "sweep --gather {}: no {CASES_CSV} there; name the --out folder of a sweep",
            dir.display()
        )),
        _ => Error::io(&path, e),
    })?;
    let plan = Plan::from_cases_csv(&text, &path.display().to_string())?;
    let mut rows = Vec::with_capacity(plan.len());
    for k in 0..plan.len() {
        let row = case::read_row(&case_dir(dir, k))?
            .filter(|r| r.status.is_finished())
            .unwrap_or_else(|| CaseRow::without_metrics(plan.shown(k), CaseStatus::Pending));
        if row.varied != plan.shown(k) {
            return Err(Error::Input(format!(
                "{}: its values {:?} are not those of case {k} in {CASES_CSV} {:?}",
                case_dir(dir, k).display(),
                row.varied,
                plan.shown(k)
            )));
        }
        rows.push(row);
    }
    let summary = write_rows(dir, &plan.keys, &rows)?;
    let figures = match plots {
        true => plots::write_plots(dir, &plan.keys, &rows)?,
        false => Vec::new(),
    };
    let mut report = report_of(dir, &rows, summary, figures);
    report.skipped = report.cases - report.pending.len();
    report.seconds = start.elapsed().as_secs_f64();
    Ok(report)
}
