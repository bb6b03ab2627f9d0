//! The one reader of numeric CSV tables: a header line of column names, then rows of numbers, one
//! per line. Blank lines and lines starting with `#` are skipped; cells are trimmed. Every row has
//! as many values as the header has names. Errors name the source and the line (1-based, as an
//! editor counts), so a user finds the cell.
//!
//! It reads what the project writes (`results.csv`, `events.csv`, `impacts.csv`: Rust's shortest
//! round-trip formatting, so a value read back is the value written, bit for bit) and what users
//! give it (a torque table, a measured swing).

use std::path::Path;

use crate::error::Error;

/// A numeric CSV table (see the module doc).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    /// The column names, trimmed.
    pub names: Vec<String>,
    /// The rows, each with one value per name.
    pub rows: Vec<Vec<f64>>,
    /// The line of each row in the source (1-based).
    pub lines: Vec<usize>,
    /// The line of the header (1-based).
    pub header_line: usize,
}

impl Table {
    /// Reads the table of the file at `path`.
    pub fn read(path: &Path) -> Result<Self, Error> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses `text`; `source` names it in errors.
    pub fn parse(text: &str, source: &str) -> Result<Self, Error> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (header_line, header) = lines
            .next()
            .ok_or_else(|| Error::Input(format!("{source}: empty file (expected a header line)")))?;
        let names: Vec<String> = header.split(',').map(|s| s.trim().to_string()).collect();
        let mut table = Self {
            names,
            header_line,
            ..Self::default()
        };
        for (no, line) in lines {
            let row = line
                .split(',')
                .map(|cell| {
                    let cell = cell.trim();
                    cell.parse::<f64>()
                        .map_err(|_| Error::Input(format!("{source}:{no}: `{cell}` is not a number (in `{line}`)")))
                })
                .collect::<Result<Vec<f64>, Error>>()?;
            if row.len() != table.names.len() {
                return Err(Error::Input(format!(
                    "{source}:{no}: {} values, the header has {} columns",
                    row.len(),
                    table.names.len()
                )));
            }
            table.rows.push(row);
            table.lines.push(no);
        }
        Ok(table)
    }

    /// The index of the column `name`, if the header has it.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// The values of the column `name`; an error names the column, the source and the columns
    /// there are.
    pub fn column(&self, name: &str, source: &str) -> Result<Vec<f64>, Error> {
        let k = self.index(name).ok_or_else(|| {
            Error::Input(format!(
                "{source}: no column `{name}` (the columns: {})",
                self.names.join(", ")
            ))
        })?;
        Ok(self.rows.iter().map(|r| r[k]).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_reads_back_what_was_written_and_bad_cells_name_their_line() {
        let t = Table::parse("# a comment\ntime_s, theta_rad\n0,0.1\n\n0.01,-2.5e-3\n", "x.csv").unwrap();
        assert_eq!(t.names, ["time_s", "theta_rad"]);
        assert_eq!(t.rows, [vec![0.0, 0.1], vec![0.01, -2.5e-3]]);
        assert_eq!((t.header_line, t.lines.as_slice()), (2, [3, 5].as_slice()));
        assert_eq!(t.column("theta_rad", "x.csv").unwrap(), [0.1, -2.5e-3]);
        let e = t.column("omega", "x.csv").unwrap_err().to_string();
        assert!(
            e.contains("no column `omega`") && e.contains("time_s, theta_rad"),
            "{e}"
        );
        let e = Table::parse("a,b\n1,2\n1,x\n", "y.csv").unwrap_err().to_string();
        assert!(e.contains("y.csv:3: `x` is not a number"), "{e}");
        let e = Table::parse("a,b\n1,2,3\n", "y.csv").unwrap_err().to_string();
        assert!(e.contains("y.csv:2: 3 values, the header has 2 columns"), "{e}");
        assert!(Table::parse("\n# only a comment\n", "z.csv").is_err());
    }
}
