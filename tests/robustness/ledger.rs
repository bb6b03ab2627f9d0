//! The campaign ledger, `tests/campaign/ledger.csv` (its rules: `tests/campaign/README.md`): one
//! row per long campaign, appended when the campaign ends, with its cases one per line in
//! `tests/campaign/runs/<seed>.csv`, from which the row's counts and per-case figures follow.
//!
//! Rows are appended with one write to a file opened for appending, so a reader sees the ledger
//! with or without the row, never half of it; the runs file is written whole
//! ([`pendulum_fem::store::write_atomically`]). A seed is spent once: a campaign whose seed has a
//! row or a runs file is refused before its first case.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::{ALONE_SECONDS, CASE_SECONDS};

/// The ledger's header, its columns in order.
pub const HEADER: &str = "date,seed,first,cases,failures,refusals,commit,limit_s,machine,wall_s,\
                          case_s_median,case_s_p90,case_s_max,newton_median,newton_p90,newton_max,\
                          cutbacks_max,draws";

/// A runs file's header: one line per case.
pub const RUNS_HEADER: &str = "index,wall,outcome,seconds,steps,newton,newton_max,cutbacks";

/// The line of the campaign README that quotes [`since_last_failure`], up to its number.
pub const QUOTE: &str = "Cases since the last failure: ";

/// The folder of the ledger, its README and the runs files.
pub fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/campaign")
}

/// Whether the machine ran other work beside the campaign, which sets the per-case limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Machine {
    Alone,
    Shared,
}

impl Machine {
    pub fn parse(word: &str) -> Option<Machine> {
        match word {
            "alone" => Some(Machine::Alone),
            "shared" => Some(Machine::Shared),
            _ => None,
        }
    }

    pub fn word(self) -> &'static str {
        match self {
            Machine::Alone => "alone",
            Machine::Shared => "shared",
        }
    }

    /// The wall time a case may take \[s\].
    pub fn limit(self) -> u64 {
        match self {
            Machine::Alone => ALONE_SECONDS,
            Machine::Shared => CASE_SECONDS,
        }
    }
}

/// How a case ended. Every outcome but [`Outcome::Passed`] and [`Outcome::Refused`] is a failure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    Passed,
    /// Stopped by an error that names its cause outside the model (`accepted_error`).
    Refused,
    /// Not finished within the per-case limit.
    Late,
    /// The energy balance missed its bar.
    Energy,
    /// A NaN in `results.csv`.
    Nan,
    /// A penetration above the contact stiffness's energy bound.
    Penetration,
    /// Any other error.
    Error,
}

impl Outcome {
    const ALL: [Outcome; 7] = [
        Outcome::Passed,
        Outcome::Refused,
        Outcome::Late,
        Outcome::Energy,
        Outcome::Nan,
        Outcome::Penetration,
        Outcome::Error,
    ];

    pub fn word(self) -> &'static str {
        match self {
            Outcome::Passed => "passed",
            Outcome::Refused => "refused",
            Outcome::Late => "late",
            Outcome::Energy => "energy",
            Outcome::Nan => "nan",
            Outcome::Penetration => "penetration",
            Outcome::Error => "error",
        }
    }

    fn parse(word: &str) -> Option<Outcome> {
        Outcome::ALL.into_iter().find(|o| o.word() == word)
    }

    pub fn failed(self) -> bool {
        !matches!(self, Outcome::Passed | Outcome::Refused)
    }
}

/// One case of a campaign, a line of its runs file. The counts are those of a passed case.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseLine {
    pub index: usize,
    /// `none`, `rigid` or `deformable`.
    pub wall: String,
    pub outcome: Outcome,
    /// Wall time from drawing the case to the end of its checks \[s\], to 0.01 s.
    pub seconds: f64,
    /// Steps, Newton iterations in all and in the output step with the most, cut-backs.
    pub counts: Option<[usize; 4]>,
}

impl CaseLine {
    fn to_csv(&self) -> String {
        let counts = self
            .counts
            .map_or_else(|| ",,,".to_string(), |c| c.map(|n| n.to_string()).join(","));
        format!(
            "{},{},{},{:.2},{counts}",
            self.index,
            self.wall,
            self.outcome.word(),
            self.seconds
        )
    }

    fn parse(line: &str) -> Result<CaseLine, String> {
        let cells: Vec<&str> = line.split(',').collect();
        if cells.len() != RUNS_HEADER.split(',').count() {
            return Err(format!("{} cells, not {}", cells.len(), RUNS_HEADER.split(',').count()));
        }
        let outcome = Outcome::parse(cells[2]).ok_or_else(|| format!("outcome {:?}", cells[2]))?;
        let counts = if cells[4..].iter().all(|c| c.is_empty()) {
            None
        } else {
            let mut c = [0; 4];
            for (k, cell) in cells[4..].iter().enumerate() {
                c[k] = number(cell)?;
            }
            Some(c)
        };
        if (outcome == Outcome::Passed) != counts.is_some() {
            return Err("steps, Newton iterations and cut-backs are given for a passed case only".into());
        }
        if !["none", "rigid", "deformable"].contains(&cells[1]) {
            return Err(format!("wall {:?}", cells[1]));
        }
        Ok(CaseLine {
            index: number(cells[0])?,
            wall: cells[1].to_string(),
            outcome,
            seconds: decimal(cells[3])?,
            counts,
        })
    }
}

/// The figures of a row that follow from its cases: counts, and the passed cases' wall time and
/// largest cut-backs and Newton iterations of a step.
#[derive(Clone, Debug, PartialEq)]
pub struct Figures {
    pub cases: usize,
    pub failures: usize,
    pub refusals: usize,
    /// Median, 90th percentile and largest \[s\].
    pub case_s: Option<[f64; 3]>,
    pub cutbacks_max: Option<usize>,
    pub newton_max: Option<usize>,
}

impl Figures {
    pub fn of(lines: &[CaseLine]) -> Figures {
        let passed: Vec<&CaseLine> = lines.iter().filter(|l| l.outcome == Outcome::Passed).collect();
        let mut seconds: Vec<f64> = passed.iter().map(|l| l.seconds).collect();
        seconds.sort_by(f64::total_cmp);
        let counts = || passed.iter().filter_map(|l| l.counts);
        Figures {
            cases: lines.len(),
            failures: lines.iter().filter(|l| l.outcome.failed()).count(),
            refusals: lines.iter().filter(|l| l.outcome == Outcome::Refused).count(),
            case_s: spread(&seconds),
            cutbacks_max: counts().map(|c| c[3]).max(),
            newton_max: counts().map(|c| c[2]).max(),
        }
    }
}

/// The median, 90th percentile and largest of sorted values, each a value of the list (nearest
/// rank: the smallest value with at least that share of the values at or below it).
pub fn spread<T: Copy>(sorted: &[T]) -> Option<[T; 3]> {
    let n = sorted.len();
    let rank = |percent: usize| sorted[(percent * n).div_ceil(100).max(1) - 1];
    (n > 0).then(|| [rank(50), rank(90), rank(100)])
}

/// One row of the ledger.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// When the campaign ended, UTC, `YYYY-MM-DDTHH:MM:SSZ`.
    pub date: String,
    pub seed: u64,
    pub first: usize,
    pub figures: Figures,
    /// `git rev-parse --short HEAD` when the campaign started, `+dirty` if the tree had changes.
    pub commit: String,
    pub limit_s: u64,
    pub machine: Machine,
    /// The campaign's wall time \[s\].
    pub wall_s: f64,
    /// Newton iterations per output step over the passed cases: median, 90th percentile, largest.
    pub newton: Option<[usize; 3]>,
    /// The version of the draws (`DRAWS` in `tests/robustness.rs`).
    pub draws: String,
}

impl Row {
    pub fn to_csv(&self) -> String {
        let f = &self.figures;
        let three = |v: Option<[String; 3]>| v.map_or_else(|| ",,".to_string(), |v| v.join(","));
        let optional = |v: Option<usize>| v.map_or_else(String::new, |n| n.to_string());
        format!(
            "{},{},{},{},{},{},{},{},{},{:.1},{},{},{},{}",
            self.date,
            self.seed,
            self.first,
            f.cases,
            f.failures,
            f.refusals,
            self.commit,
            self.limit_s,
            self.machine.word(),
            self.wall_s,
            three(f.case_s.map(|v| v.map(|s| format!("{s:.2}")))),
            three(self.newton.map(|v| v.map(|n| n.to_string()))),
            optional(f.cutbacks_max),
            self.draws
        )
    }

    pub fn parse(line: &str) -> Result<Row, String> {
        let cells: Vec<&str> = line.split(',').collect();
        let columns = HEADER.split(',').count();
        if cells.len() != columns {
            return Err(format!("{} cells, not {columns}", cells.len()));
        }
        let optional = |cell: &str| (!cell.is_empty()).then(|| number(cell)).transpose();
        let date = cells[0];
        if !is_utc(date) {
            return Err(format!("date {date:?} is not YYYY-MM-DDTHH:MM:SSZ"));
        }
        let commit = cells[6];
        let hash = commit.strip_suffix("+dirty").unwrap_or(commit);
        if hash.len() < 7 || !hash.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(format!("commit {commit:?}"));
        }
        let machine = Machine::parse(cells[8]).ok_or_else(|| format!("machine {:?}: alone or shared", cells[8]))?;
        let limit_s: u64 = number(cells[7])?;
        if limit_s != machine.limit() {
            return Err(format!(
                "limit {limit_s} s on a machine {}: its limit is {} s",
                machine.word(),
                machine.limit()
            ));
        }
        let case_s = match (cells[10], cells[11], cells[12]) {
            ("", "", "") => None,
            (a, b, c) => Some([decimal(a)?, decimal(b)?, decimal(c)?]),
        };
        let newton = match (optional(cells[13])?, optional(cells[14])?, optional(cells[15])?) {
            (None, None, None) => None,
            (Some(a), Some(b), Some(c)) => Some([a, b, c]),
            _ => return Err("Newton iterations: all three figures or none".into()),
        };
        let row = Row {
            date: date.to_string(),
            seed: number(cells[1])?,
            first: number(cells[2])?,
            figures: Figures {
                cases: number(cells[3])?,
                failures: number(cells[4])?,
                refusals: number(cells[5])?,
                case_s,
                cutbacks_max: optional(cells[16])?,
                newton_max: newton.map(|n| n[2]),
            },
            commit: commit.to_string(),
            limit_s,
            machine,
            wall_s: decimal(cells[9])?,
            newton,
            draws: cells[17].to_string(),
        };
        let f = &row.figures;
        if f.cases == 0 || f.failures + f.refusals > f.cases {
            return Err(format!(
                "{} failures and {} refusals of {} cases",
                f.failures, f.refusals, f.cases
            ));
        }
        let ordered = |v: [f64; 3]| v[0] <= v[1] && v[1] <= v[2];
        if !f.case_s.is_none_or(ordered) || !row.newton.is_none_or(|n| ordered(n.map(|k| k as f64))) {
            return Err("a median above its 90th percentile or the 90th percentile above the largest".into());
        }
        if row.draws.is_empty() {
            return Err("no draws version".into());
        }
        Ok(row)
    }
}

fn number<T: std::str::FromStr>(cell: &str) -> Result<T, String> {
    cell.parse().map_err(|_| format!("{cell:?} is not a whole number"))
}

fn decimal(cell: &str) -> Result<f64, String> {
    cell.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite() && *x >= 0.0)
        .ok_or_else(|| format!("{cell:?} is not a number of seconds"))
}

fn is_utc(date: &str) -> bool {
    let b = date.as_bytes();
    b.len() == 20
        && b.iter().enumerate().all(|(k, &c)| match k {
            4 | 7 => c == b'-',
            10 => c == b'T',
            13 | 16 => c == b':',
            19 => c == b'Z',
            _ => c.is_ascii_digit(),
        })
}

/// The rows of the ledger at `path`, checked: the header, every row, a newline after the last,
/// and no seed twice.
pub fn read(path: &Path) -> Result<Vec<Row>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    if !text.ends_with('\n') {
        return Err(format!("{}: its last line has no newline", path.display()));
    }
    let mut lines = text.lines();
    if lines.next() != Some(HEADER) {
        return Err(format!("{}: the header is not\n{HEADER}", path.display()));
    }
    let mut rows: Vec<Row> = Vec::new();
    for (k, line) in lines.enumerate() {
        let row = Row::parse(line).map_err(|e| format!("{} line {}: {e}\n{line}", path.display(), k + 2))?;
        if rows.iter().any(|r| r.seed == row.seed) {
            return Err(format!("{} line {}: seed {} twice", path.display(), k + 2, row.seed));
        }
        rows.push(row);
    }
    Ok(rows)
}

/// The cases of the rows after the last row with a failure (of all rows if none failed): the
/// count goes on across versions of the draws.
pub fn since_last_failure(rows: &[Row]) -> usize {
    let after = rows.iter().rposition(|r| r.figures.failures > 0).map_or(0, |k| k + 1);
    rows[after..].iter().map(|r| r.figures.cases).sum()
}

/// The path of the runs file of `seed`.
pub fn runs_path(seed: u64) -> PathBuf {
    folder().join("runs").join(format!("{seed}.csv"))
}

/// The cases of a runs file, checked: the header and every line.
pub fn read_runs(path: &Path) -> Result<Vec<CaseLine>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    if lines.next() != Some(RUNS_HEADER) {
        return Err(format!("{}: the header is not {RUNS_HEADER}", path.display()));
    }
    lines
        .enumerate()
        .map(|(k, line)| CaseLine::parse(line).map_err(|e| format!("{} line {}: {e}", path.display(), k + 2)))
        .collect()
}

/// Checks that `row` states what its runs file's cases give: a case per index from `first` on,
/// and the figures that follow from them.
pub fn check_against_runs(row: &Row, cases: &[CaseLine]) -> Result<(), String> {
    let indices: Vec<usize> = cases.iter().map(|c| c.index).collect();
    let expected: Vec<usize> = (row.first..row.first + cases.len()).collect();
    if indices != expected {
        return Err(format!(
            "seed {}: its runs file's cases are not {}…",
            row.seed, row.first
        ));
    }
    let figures = Figures::of(cases);
    // the Newton iterations' median and 90th percentile are over every step, not in the runs file
    let stated = Figures {
        newton_max: row.newton.map(|n| n[2]),
        ..row.figures.clone()
    };
    if stated != figures {
        return Err(format!(
            "seed {}: the row states {stated:?}, its runs file gives {figures:?}",
            row.seed
        ));
    }
    Ok(())
}

/// `unix` seconds as a UTC date, `YYYY-MM-DDTHH:MM:SSZ` (the proleptic Gregorian calendar).
pub fn utc(unix: u64) -> String {
    let days = (unix / 86_400) as i64;
    let s = unix % 86_400;
    // days since 0000-03-01, in eras of 400 years (146097 days)
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        s / 3600,
        s % 3600 / 60,
        s % 60
    )
}

/// The commit checked out, `+dirty` if the tree has changes outside `tests/campaign/` (the
/// ledger, its README and the runs files are no part of what a campaign tests).
pub fn commit() -> Result<String, String> {
    let git = |args: &[&str]| -> Result<String, String> {
        let out = std::process::Command::new("git")
            .arg("-C")
            .arg(env!("CARGO_MANIFEST_DIR"))
            .args(args)
            .output()
            .map_err(|e| format!("git: {e}"))?;
        if !out.status.success() {
            return Err(format!(
                "git {}: {}",
                args.join(" "),
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    };
    let hash = git(&["rev-parse", "--short", "HEAD"])?.trim().to_string();
    let changes = git(&["status", "--porcelain", "--", ".", ":(exclude)tests/campaign"])?;
    Ok(if changes.trim().is_empty() {
        hash
    } else {
        format!("{hash}+dirty")
    })
}

/// A campaign that will append its row: what is known at its start.
pub struct Campaign {
    pub seed: u64,
    pub first: usize,
    pub machine: Machine,
    pub commit: String,
    pub draws: &'static str,
}

impl Campaign {
    /// Checks that `seed` is new to the ledger (no row, no runs file) and takes the commit.
    pub fn start(seed: u64, first: usize, machine: Machine, draws: &'static str) -> Result<Campaign, String> {
        let rows = read(&folder().join("ledger.csv"))?;
        if rows.iter().any(|r| r.seed == seed) || runs_path(seed).exists() {
            return Err(format!(
                "seed {seed} is in the campaign ledger already: a campaign draws a seed never run before"
            ));
        }
        Ok(Campaign {
            seed,
            first,
            machine,
            commit: commit()?,
            draws,
        })
    }

    /// Writes the runs file of `cases` (sorted by index), appends the row and updates the README's
    /// quoted count; returns the row. `iterations` are the Newton iterations of every output step
    /// of the passed cases.
    pub fn finish(&self, mut cases: Vec<CaseLine>, mut iterations: Vec<usize>, wall_s: f64) -> Result<Row, String> {
        cases.sort_by_key(|c| c.index);
        for c in &mut cases {
            c.seconds = (c.seconds * 100.0).round() / 100.0;
        }
        iterations.sort_unstable();
        let now = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_err(|e| e.to_string())?;
        let row = Row {
            date: utc(now.as_secs()),
            seed: self.seed,
            first: self.first,
            figures: Figures::of(&cases),
            commit: self.commit.clone(),
            limit_s: self.machine.limit(),
            machine: self.machine,
            wall_s,
            newton: spread(&iterations),
            draws: self.draws.to_string(),
        };
        let ledger = folder().join("ledger.csv");
        // the seed again: a campaign of the same seed may have ended meanwhile
        let rows = read(&ledger)?;
        if rows.iter().any(|r| r.seed == self.seed) || runs_path(self.seed).exists() {
            return Err(format!("seed {} was recorded while this campaign ran", self.seed));
        }
        pendulum_fem::store::write_atomically(&runs_path(self.seed), |w| {
            writeln!(w, "{RUNS_HEADER}")?;
            for c in &cases {
                writeln!(w, "{}", c.to_csv())?;
            }
            Ok(())
        })
        .map_err(|e| e.to_string())?;
        let line = format!("{}\n", row.to_csv());
        std::fs::OpenOptions::new()
            .append(true)
            .open(&ledger)
            .and_then(|mut f| f.write_all(line.as_bytes()))
            .map_err(|e| format!("{}: {e}", ledger.display()))?;
        let rows = read(&ledger)?;
        quote(&folder().join("README.md"), since_last_failure(&rows))?;
        Ok(row)
    }
}

/// The count the README at `path` quotes on its line starting with [`QUOTE`].
pub fn quoted(path: &Path) -> Result<usize, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix(QUOTE))
        .ok_or_else(|| format!("{}: no line starting {QUOTE:?}", path.display()))?;
    let digits: String = line
        .chars()
        .skip_while(|c| *c == '*')
        .take_while(char::is_ascii_digit)
        .collect();
    number(&digits)
}

/// Sets the count the README at `path` quotes to `count`.
pub fn quote(path: &Path, count: usize) -> Result<(), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut out = String::new();
    for line in text.lines() {
        if line.starts_with(QUOTE) {
            out.push_str(&format!("{QUOTE}**{count}**."));
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    pendulum_fem::store::write_bytes_atomically(path, out.as_bytes()).map_err(|e| e.to_string())
}
