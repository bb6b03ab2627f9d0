//! Streaming CSV output: one row per step, written as it is computed (nothing is held for the
//! whole run). Numbers use Rust's shortest round-trip formatting, so a value read back is
//! bit-identical. Rows are flushed when the writer is finished or dropped, including on errors, so
//! a stopped run leaves every completed row on disk.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::Error;

/// A CSV file being written row by row.
pub struct CsvWriter {
    path: PathBuf,
    out: std::io::BufWriter<std::fs::File>,
    columns: usize,
}

impl CsvWriter {
    /// Creates `path` and writes the header line.
    pub fn create(path: &Path, header: &str) -> Result<Self, Error> {
        let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
        let mut out = std::io::BufWriter::new(file);
        writeln!(out, "{header}").map_err(|e| Error::io(path, e))?;
        Ok(Self {
            path: path.to_path_buf(),
            out,
            columns: header.split(',').count(),
        })
    }

    /// Opens `path`, an existing CSV whose first line is `header`, to append rows to it (a
    /// restarted run, [`crate::driver::run`]).
    pub fn append(path: &Path, header: &str) -> Result<Self, Error> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        let first = text.lines().next().unwrap_or_default();
        if first != header {
            return Err(Error::Input(format!(
                "{}: the header `{first}` is not this program's `{header}`",
                path.display()
            )));
        }
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .map_err(|e| Error::io(path, e))?;
        Ok(Self {
            path: path.to_path_buf(),
            out: std::io::BufWriter::new(file),
            columns: header.split(',').count(),
        })
    }

    /// Writes the rows so far to the file (before a checkpoint, so that the file holds at least
    /// every row up to it).
    pub fn flush(&mut self) -> Result<(), Error> {
        self.out.flush().map_err(|e| Error::io(&self.path, e))
    }

    /// Appends one row.
    ///
    /// # Panics
    /// If the number of values differs from the number of header columns.
    pub fn row(&mut self, values: &[f64]) -> Result<(), Error> {
        assert_eq!(values.len(), self.columns, "CSV row length must match the header");
        let line: Vec<String> = values.iter().map(|v| v.to_string()).collect();
        writeln!(self.out, "{}", line.join(",")).map_err(|e| Error::io(&self.path, e))
    }

    /// Flushes everything to disk.
    pub fn finish(mut self) -> Result<PathBuf, Error> {
        self.out.flush().map_err(|e| Error::io(&self.path, e))?;
        Ok(self.path)
    }
}

/// Reads a numeric CSV with a header line; returns the header names and the rows.
/// Errors name the file and the line.
pub fn read_numeric_csv(path: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>), Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
    let (_, header) = lines
        .next()
        .ok_or_else(|| Error::Input(format!("{}: empty file", path.display())))?;
    let names: Vec<String> = header.split(',').map(|s| s.trim().to_string()).collect();
    let mut rows = Vec::new();
    for (no, line) in lines {
        let row: Result<Vec<f64>, _> = line.split(',').map(|s| s.trim().parse::<f64>()).collect();
        let row = row.map_err(|e| Error::Input(format!("{}:{}: {e} in `{line}`", path.display(), no + 1)))?;
        if row.len() != names.len() {
            return Err(Error::Input(format!(
                "{}:{}: {} values, the header has {} columns",
                path.display(),
                no + 1,
                row.len(),
                names.len()
            )));
        }
        rows.push(row);
    }
    Ok((names, rows))
}
