//! Streaming CSV output: one row per step (or event), written as it is computed (nothing is held
//! for the whole run); a restarted run appends to the files it continues. Numbers use Rust's
//! shortest round-trip formatting, so a value read back is bit-identical. Rows are flushed when the
//! writer is finished or dropped, including on errors, so a stopped run leaves every completed row
//! on disk.

use std::io::{BufRead, Write};
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
        let mut file = std::fs::OpenOptions::new()
            .read(true)
            .append(true)
            .open(path)
            .map_err(|e| Error::io(path, e))?;
        let mut first = String::new();
        std::io::BufReader::new(&mut file)
            .read_line(&mut first)
            .map_err(|e| Error::io(path, e))?;
        let first = first.trim_end_matches(['\n', '\r']);
        if first != header {
            return Err(Error::Input(format!(
                "{}: the header `{first}` is not this program's `{header}`",
                path.display()
            )));
        }
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
        self.line(&line.join(","))
    }

    /// Appends one row given as its text, without the line break (a row with a text cell, such as
    /// `events.csv`'s).
    pub fn line(&mut self, row: &str) -> Result<(), Error> {
        writeln!(self.out, "{row}").map_err(|e| Error::io(&self.path, e))
    }

    /// Flushes everything to disk.
    pub fn finish(mut self) -> Result<PathBuf, Error> {
        self.out.flush().map_err(|e| Error::io(&self.path, e))?;
        Ok(self.path)
    }
}
