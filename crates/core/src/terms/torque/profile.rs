//! The time profiles of the torque: the `[torque]` section's `M(t)` (constant, step, ramp, sine,
//! table) and its peak, and the [`TorqueTable`] of a `profile = "table"` CSV, read once and
//! interpolated linearly.

use super::Torque;
use crate::config;
use crate::error::Error;
use std::path::Path;

/// The samples of a `profile = "table"` torque: `(time, torque)` pairs, evaluated by
/// piecewise-linear interpolation, constant beyond both ends.
#[derive(Clone, Debug, PartialEq)]
pub struct TorqueTable {
    /// Sample times, strictly increasing \[s\] (at least two).
    pub times: Vec<f64>,
    /// Torques at those times \[N·m\].
    pub torques: Vec<f64>,
}

impl TorqueTable {
    /// Reads a table: a CSV with the header `time_s,torque_Nm` and at least two rows of numbers
    /// with strictly increasing times. Blank lines and lines starting with `#` are skipped.
    pub fn read(path: &Path) -> Result<Self, Error> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::Config(format!(
                "torque.file = {}: cannot read the torque table: {e}",
                path.display()
            ))
        })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses the text of a table ([`crate::store::Table`]'s rules); `source` names the file in
    /// error messages.
    pub fn parse(text: &str, source: &str) -> Result<Self, Error> {
        let err = |line: usize, msg: String| Error::Input(format!("{source}:{line}: {msg}"));
        let table = crate::store::Table::parse(text, source)?;
        if table.names != ["time_s", "torque_Nm"] {
            let header = table.names.join(",");
            return Err(err(
                table.header_line,
                format!("header `{header}`: expected `time_s,torque_Nm`"),
            ));
        }
        let (mut times, mut torques) = (Vec::new(), Vec::new());
        for (row, &no) in table.rows.iter().zip(&table.lines) {
            let v = [row[0], row[1]];
            if let Some(x) = v.iter().find(|x| !x.is_finite()) {
                return Err(err(no, format!("`{x}` is not a finite number")));
            }
            if let Some(&last) = times.last() {
                if v[0] <= last {
                    return Err(err(
                        no,
                        format!(
                            "time {} s is not after the previous time {last} s (times must increase strictly)",
                            v[0]
                        ),
                    ));
                }
            }
            times.push(v[0]);
            torques.push(v[1]);
        }
        if times.len() < 2 {
            return Err(Error::Input(format!(
                "{source}: the torque table has {} row(s); at least 2 are needed",
                times.len()
            )));
        }
        Ok(Self { times, torques })
    }

    /// The interpolated torque at `t` \[N·m\].
    pub fn value(&self, t: f64) -> f64 {
        let (times, torques) = (&self.times, &self.torques);
        let n = times.len();
        if t <= times[0] {
            return torques[0];
        }
        if t >= times[n - 1] {
            return torques[n - 1];
        }
        // first index with times[k] > t; 1 ≤ k ≤ n − 1
        let k = times.partition_point(|&x| x <= t);
        let (t0, t1) = (times[k - 1], times[k]);
        let (m0, m1) = (torques[k - 1], torques[k]);
        m0 + (m1 - m0) * (t - t0) / (t1 - t0)
    }
}

impl Torque {
    /// The largest `|M(t)|` of the profile over all times \[N·m\] (a table's largest sample:
    /// its linear interpolation never exceeds it).
    pub fn peak(&self) -> f64 {
        use config::TorqueProfile as P;
        match (self.profile.profile, &self.table) {
            (P::None, _) => 0.0,
            (P::Table, Some(table)) => table.torques.iter().fold(0.0f64, |a, m| a.max(m.abs())),
            _ => self.profile.amplitude.abs(),
        }
    }

    /// The profile's `M(t)` \[N·m\], counter-clockwise positive (see [`config::TorqueProfile`]).
    pub fn value(&self, t: f64) -> f64 {
        use config::TorqueProfile as P;
        let c = &self.profile;
        match c.profile {
            P::None => 0.0,
            P::Constant => c.amplitude,
            P::Step => {
                if t >= c.start {
                    c.amplitude
                } else {
                    0.0
                }
            }
            P::Ramp => c.amplitude * ((t - c.start) / c.duration).clamp(0.0, 1.0),
            P::Sine => {
                if t >= c.start {
                    c.amplitude * (std::f64::consts::TAU * c.frequency * (t - c.start) + c.phase).sin()
                } else {
                    0.0
                }
            }
            P::Table => self.table.as_ref().map_or(0.0, |table| table.value(t)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_interpolates_linearly_and_extrapolates_constantly() {
        let p = TorqueTable::parse("time_s,torque_Nm\n0.5,1\n1.0,3\n2.0,-1\n", "t.csv").unwrap();
        assert_eq!(p.value(0.0), 1.0);
        assert_eq!(p.value(0.5), 1.0);
        assert!((p.value(0.75) - 2.0).abs() < 1e-15);
        assert_eq!(p.value(1.0), 3.0);
        assert!((p.value(1.5) - 1.0).abs() < 1e-15);
        assert_eq!(p.value(5.0), -1.0);
    }
}
