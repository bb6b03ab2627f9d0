//! Checkpoints and restart: the latest snapshot and the configuration of a run written beside its
//! results, and a restarted run's return to its checkpoint (the state restored, `results.csv` and
//! `impacts.csv` cut after the checkpoint's step).

use pendulum_fem_core::simulation::{Simulation, StepRecord};
use pendulum_fem_core::{Config, Error};

use crate::rows::{csv_values, record_of_row};
use pendulum_fem_core::store::write_atomically;

/// The latest snapshot of a run with checkpoints ([`pendulum_fem_core::Snapshot::to_bytes`]).
pub const CHECKPOINT_SNAP: &str = "checkpoint.snap";

/// The configuration of a run with checkpoints, read by `run --restart`.
pub const CHECKPOINT_TOML: &str = "checkpoint.toml";

/// Writes the snapshot of `sim` to `dir/checkpoint.snap` atomically (a temporary file, then a
/// rename: a run killed meanwhile leaves the previous checkpoint intact).
pub(crate) fn write_checkpoint(dir: &std::path::Path, sim: &Simulation) -> Result<(), Error> {
    let path = dir.join(CHECKPOINT_SNAP);
    let bytes = sim.snapshot().to_bytes();
    write_atomically(&path, |w| w.write_all(&bytes))
}

/// Writes the configuration of a run with checkpoints to `dir/checkpoint.toml` (file paths made
/// absolute, so that it reads back from any folder).
pub(crate) fn write_checkpoint_config(dir: &std::path::Path, cfg: &Config) -> Result<(), Error> {
    let text = crate::files::portable_toml(cfg, CHECKPOINT_TOML)?;
    let path = dir.join(CHECKPOINT_TOML);
    write_atomically(&path, |w| w.write_all(text.as_bytes()))
}

/// The records before a restarted run's checkpoint and the `(step, time)` of every row up to and
/// including it.
type Resumed = (Vec<StepRecord>, Vec<(usize, f64)>);

/// A restarted run: the state is restored from the checkpoint, `results.csv` is cut after the
/// checkpoint's row; returns the rows before the checkpoint's (as records) and the `(step, time)`
/// of every row up to and including it.
pub(crate) fn resume(dir: &std::path::Path, sim: &mut Simulation) -> Result<Resumed, Error> {
    let snap_path = dir.join(CHECKPOINT_SNAP);
    let bytes = std::fs::read(&snap_path).map_err(|e| Error::io(&snap_path, e))?;
    let snap = pendulum_fem_core::Snapshot::from_bytes(&bytes, &snap_path.display().to_string())?;
    sim.restore(&snap)
        .map_err(|e| Error::Input(format!("{}: {e}", snap_path.display())))?;
    let k = snap.step();
    let csv_path = dir.join("results.csv");
    let text = std::fs::read_to_string(&csv_path).map_err(|e| Error::io(&csv_path, e))?;
    // the header and the rows of steps 0..=k, each ending in a newline
    let mut end = 0;
    for line in 0..k + 2 {
        match text[end..].find('\n') {
            Some(i) => end += i + 1,
            None => {
                return Err(Error::Input(format!(
                    "{}: {} complete rows, but the checkpoint is at step {k}: the file does not belong to it",
                    csv_path.display(),
                    line.saturating_sub(1)
                )))
            }
        }
    }
    let columns = csv_values(&sim.record(0)).len();
    let mut rows = Vec::with_capacity(k + 1);
    for (i, line) in text[..end].lines().skip(1).enumerate() {
        let values: Result<Vec<f64>, _> = line.split(',').map(str::parse::<f64>).collect();
        match values {
            Ok(v) if v.len() == columns => rows.push(record_of_row(i, &v)),
            _ => {
                return Err(Error::Input(format!(
                    "{}:{}: not a row of {columns} numbers",
                    csv_path.display(),
                    i + 2
                )))
            }
        }
    }
    let its = sim.last_newton_iterations();
    let now = csv_values(&sim.record(its));
    let row_k = csv_values(&rows[k]);
    if now.iter().zip(&row_k).any(|(a, b)| a.to_bits() != b.to_bits()) {
        return Err(Error::Input(format!(
            "{}: the row of step {k} differs from the state of {}: they are not of the same run",
            csv_path.display(),
            snap_path.display()
        )));
    }
    let file = std::fs::OpenOptions::new()
        .write(true)
        .open(&csv_path)
        .map_err(|e| Error::io(&csv_path, e))?;
    file.set_len(end as u64).map_err(|e| Error::io(&csv_path, e))?;
    let times = rows.iter().map(|r| (r.step, r.time)).collect();
    rows.truncate(k);
    Ok((rows, times))
}

/// Cuts the rows of a CSV file (a header line, then rows whose first column is the time) after
/// time `t`, for a restarted run: the rows after its checkpoint are computed again.
pub(crate) fn cut_rows_after(path: &std::path::Path, t: f64) -> Result<(), Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let mut kept = String::new();
    for (i, line) in text.lines().enumerate() {
        let time = line.split(',').next().and_then(|c| c.parse::<f64>().ok());
        if i == 0 || time.is_some_and(|time| time <= t) {
            kept.push_str(line);
            kept.push('\n');
        }
    }
    write_atomically(path, |w| w.write_all(kept.as_bytes()))
}

#[cfg(test)]
mod tests {
    use super::cut_rows_after;

    #[test]
    fn a_restart_cuts_the_impact_rows_after_its_checkpoint_and_keeps_the_header() {
        let dir = std::env::temp_dir().join(format!("pendulum-fem-cut-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("impacts.csv");
        std::fs::write(&path, "time_s,theta_rad\n0.1,1\n0.2,2\n0.25,3\n0.3,4\n").unwrap();
        cut_rows_after(&path, 0.25).unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "time_s,theta_rad\n0.1,1\n0.2,2\n0.25,3\n"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
