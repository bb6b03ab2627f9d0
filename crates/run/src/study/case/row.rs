//! A case's row of the study's summary: how the case ended, its metrics, the columns, and the row
//! as CSV cells (written in the shortest round-trip form) and read back from a summary line.

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
