//! `status.json`: how a run ended, in every run folder.
//!
//! Written as `"running"` when the run starts (so a folder whose process was killed says so) and
//! rewritten atomically when it ends:
//!
//! ```json
//! {"status": "interrupted", "step": 43, "time_s": 0.43, "end_time_s": 1.0, "error": null}
//! ```
//!
//! `status` is `"running"`, `"ok"` (reached `end_time_s`), `"interrupted"` (Ctrl-C or SIGTERM,
//! stopped at a step boundary) or `"failed"` (`error` holds the message and its causes). `step` and
//! `time_s` are those of the last row of `results.csv` (`null` when the run failed before its first
//! row, e.g. in the mesher).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::Error;

/// Name of the status file in the run folder.
pub const STATUS_JSON: &str = "status.json";

/// The content of `status.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunStatus {
    /// `"running"`, `"ok"`, `"interrupted"` or `"failed"`.
    pub status: String,
    /// Last step written to `results.csv`.
    pub step: Option<usize>,
    /// Its time \[s\].
    pub time_s: Option<f64>,
    /// `time.end` of the run \[s\].
    pub end_time_s: f64,
    /// The error of a failed run, with its causes.
    pub error: Option<String>,
    /// The warnings of the run (absent when there are none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

impl RunStatus {
    fn new(status: &str, end_time_s: f64, reached: Option<(usize, f64)>, error: Option<String>) -> Self {
        Self {
            status: status.into(),
            step: reached.map(|r| r.0),
            time_s: reached.map(|r| r.1),
            end_time_s,
            error,
            warnings: Vec::new(),
        }
    }

    /// The same status with the run's warnings.
    pub fn with_warnings(mut self, warnings: &[String]) -> Self {
        self.warnings = warnings.to_vec();
        self
    }

    /// A run that has started.
    pub fn running(end_time_s: f64) -> Self {
        Self::new("running", end_time_s, None, None)
    }

    /// A run that reached its end time.
    pub fn ok(end_time_s: f64, reached: Option<(usize, f64)>) -> Self {
        Self::new("ok", end_time_s, reached, None)
    }

    /// A run stopped by a signal at a step boundary.
    pub fn interrupted(end_time_s: f64, reached: Option<(usize, f64)>) -> Self {
        Self::new("interrupted", end_time_s, reached, None)
    }

    /// A run stopped by an error.
    pub fn failed(end_time_s: f64, reached: Option<(usize, f64)>, error: &Error) -> Self {
        Self::new("failed", end_time_s, reached, Some(error_chain(error)))
    }

    /// Writes the status to `path` (atomically).
    pub fn write(&self, path: &Path) -> Result<(), Error> {
        let text = serde_json::to_string_pretty(self).expect("a status serialises");
        pendulum_fem_core::store::write_atomically(path, |w| writeln!(w, "{text}"))
    }

    /// Reads a status file.
    pub fn read(path: &Path) -> Result<Self, Error> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        serde_json::from_str(&text).map_err(|e| Error::Input(format!("{}: {e}", path.display())))
    }
}

/// The error's message followed by each cause that adds something (`": "`-separated).
pub fn error_chain(error: &Error) -> String {
    let mut text = error.to_string();
    let mut source = std::error::Error::source(error);
    while let Some(s) = source {
        let m = s.to_string();
        if !text.contains(&m) {
            text.push_str(": ");
            text.push_str(&m);
        }
        source = s.source();
    }
    text
}
