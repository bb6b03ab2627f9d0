//! Checkpoints and restart: the latest snapshot and the configuration of a run written beside its
//! results, and a restarted run's return to its checkpoint: the snapshot read and checked against
//! the model once, the state restored, and the files it continues cut after the checkpoint
//! (`results.csv` after the checkpoint's step, `impacts.csv` after its time, `events.csv` after its
//! events), each truncated in place once all are checked, and appended to from there.

use std::path::{Path, PathBuf};

use pendulum_fem_core::simulation::{ContactEvent, Simulation, StepRecord};
use pendulum_fem_core::store::{write_atomically, Table};
use pendulum_fem_core::{Config, Error, Snapshot};

pub use crate::outdir::names::{CHECKPOINT_SNAP, CHECKPOINT_TOML};
use crate::rows::{csv_values, event_row, records_of_table};

/// Writes the snapshot of `sim` to `dir/checkpoint.snap` atomically (a temporary file, then a
/// rename: a run killed meanwhile leaves the previous checkpoint intact).
pub(crate) fn write_checkpoint(dir: &Path, sim: &Simulation) -> Result<(), Error> {
    let path = dir.join(CHECKPOINT_SNAP);
    let bytes = sim.snapshot().to_bytes();
    write_atomically(&path, |w| w.write_all(&bytes))
}

/// Writes the configuration of a run with checkpoints to `dir/checkpoint.toml` (file paths made
/// absolute, so that it reads back from any folder).
pub(crate) fn write_checkpoint_config(dir: &Path, cfg: &Config) -> Result<(), Error> {
    let text = crate::files::portable_toml(cfg, CHECKPOINT_TOML)?;
    let path = dir.join(CHECKPOINT_TOML);
    write_atomically(&path, |w| w.write_all(text.as_bytes()))
}

/// Reads and decodes the checkpoint of the run in `dir`.
pub(crate) fn read_checkpoint(dir: &Path) -> Result<Snapshot, Error> {
    let path = dir.join(CHECKPOINT_SNAP);
    let bytes = std::fs::read(&path).map_err(|e| Error::io(&path, e))?;
    Snapshot::from_bytes(&bytes, &path.display().to_string())
}

/// A cut of a file after its first `len` bytes, to be made once every file of a restart is checked
/// (so that a refused restart leaves them all as they were).
#[must_use]
#[derive(Debug)]
pub(crate) struct Cut {
    path: PathBuf,
    len: usize,
}

impl Cut {
    /// Cuts the file.
    pub(crate) fn apply(self) -> Result<(), Error> {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(&self.path)
            .map_err(|e| Error::io(&self.path, e))?;
        file.set_len(self.len as u64).map_err(|e| Error::io(&self.path, e))
    }
}

/// What a restarted run returns to: the records before its checkpoint and the `(step, time)` of
/// every `results.csv` row up to and including the checkpoint's.
pub(crate) struct Resumed {
    /// The records of the `results.csv` rows before the checkpoint's.
    pub rows: Vec<StepRecord>,
    /// The `(step, time)` of every `results.csv` row up to and including the checkpoint's.
    pub times: Vec<(usize, f64)>,
    /// The cut of `results.csv` after the checkpoint's row.
    pub cut: Cut,
}

/// A restarted run: the state is restored from `snapshot` (the checkpoint of the run in `dir`);
/// `results.csv` must hold the rows up to the checkpoint's, whose values must be the restored
/// state's bit for bit, and is to be cut after it.
pub(crate) fn resume(dir: &Path, sim: &mut Simulation, snapshot: &Snapshot) -> Result<Resumed, Error> {
    let snap_path = dir.join(CHECKPOINT_SNAP);
    sim.restore(snapshot)
        .map_err(|e| Error::Input(format!("{}: {e}", snap_path.display())))?;
    let k = snapshot.step();
    let csv_path = dir.join(crate::outdir::names::RESULTS_CSV);
    let source = csv_path.display().to_string();
    let text = std::fs::read_to_string(&csv_path).map_err(|e| Error::io(&csv_path, e))?;
    // the header and the rows of steps 0..=k, each ending in a line break
    let lines: Vec<&str> = text.split_inclusive('\n').take(k + 2).collect();
    let complete = lines.iter().take_while(|l| l.ends_with('\n')).count();
    if complete < k + 2 {
        return Err(Error::Input(format!(
            "{source}: {} complete rows, but the checkpoint is at step {k}: the file does not belong to it",
            complete.saturating_sub(1)
        )));
    }
    let end: usize = lines.iter().map(|l| l.len()).sum();
    let rows = records_of_table(&Table::parse(&text[..end], &source)?, &source)?;
    if rows.len() != k + 1 {
        return Err(Error::Input(format!(
            "{source}: {} rows up to the checkpoint's line, but the checkpoint is at step {k}: the file does not \
             belong to it",
            rows.len()
        )));
    }
    let now = csv_values(&sim.record(sim.last_newton_iterations()));
    if now
        .iter()
        .zip(&csv_values(&rows[k]))
        .any(|(a, b)| a.to_bits() != b.to_bits())
    {
        return Err(Error::Input(format!(
            "{source}: the row of step {k} differs from the state of {}: they are not of the same run",
            snap_path.display()
        )));
    }
    let times = rows.iter().map(|r| (r.step, r.time)).collect();
    let mut rows = rows;
    rows.truncate(k);
    let cut = Cut {
        path: csv_path,
        len: end,
    };
    Ok(Resumed { rows, times, cut })
}

/// The cut of a CSV file of rows in time order (a header line, then rows whose first column is the
/// time) after its last complete row at or before time `t`, for a restarted run: the rows after
/// its checkpoint are computed again. A row without its line break (a run killed while writing it)
/// is cut too. Returns the text kept and the cut.
pub(crate) fn rows_until(path: &Path, t: f64) -> Result<(String, Cut), Error> {
    let mut text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let mut end = 0;
    for (i, line) in text.split_inclusive('\n').enumerate() {
        let time = line.split(',').next().and_then(|c| c.trim().parse::<f64>().ok());
        if !line.ends_with('\n') || (i > 0 && !time.is_some_and(|time| time <= t)) {
            break;
        }
        end += line.len();
    }
    text.truncate(end);
    let cut = Cut {
        path: path.to_path_buf(),
        len: end,
    };
    Ok((text, cut))
}

/// The records the `impacts.csv` of a restarted run keeps up to its checkpoint's time `t`
/// ([`rows_until`]), and its cut after them.
pub(crate) fn impacts_until(path: &Path, t: f64) -> Result<(Vec<StepRecord>, Cut), Error> {
    let (kept, cut) = rows_until(path, t)?;
    let source = path.display().to_string();
    Ok((records_of_table(&Table::parse(&kept, &source)?, &source)?, cut))
}

/// The cut of the `events.csv` of a restarted run after the rows of `events`, the checkpoint's
/// contact events, which must be its first rows: the events after the checkpoint happen again. (A
/// cut by time would not do: an impact's start is dated back to the first touch, which may lie
/// before a checkpoint taken while the head grazed the wall.)
pub(crate) fn events_until(path: &Path, events: &[ContactEvent]) -> Result<Cut, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let mut end = 0;
    for (i, line) in text.split_inclusive('\n').take(events.len() + 1).enumerate() {
        let row = line.strip_suffix('\n');
        let expected = match i {
            0 => crate::rows::EVENTS_HEADER.to_string(),
            _ => event_row(&events[i - 1]),
        };
        if row != Some(expected.as_str()) {
            return Err(Error::Input(format!(
                "{}:{}: `{}` is not the checkpoint's `{expected}`: the file does not belong to it",
                path.display(),
                i + 1,
                line.trim_end()
            )));
        }
        end += line.len();
    }
    let rows = text[..end].lines().count().saturating_sub(1);
    if rows < events.len() {
        return Err(Error::Input(format!(
            "{}: {rows} events, but the checkpoint has {}: the file does not belong to it",
            path.display(),
            events.len()
        )));
    }
    Ok(Cut {
        path: path.to_path_buf(),
        len: end,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rows::header;
    use pendulum_fem_core::simulation::{ContactEventKind, ContactRecord};

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("pendulum-fem-cut-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn record(time: f64) -> StepRecord {
        StepRecord {
            time,
            theta: 10.0 * time,
            contact: Some(ContactRecord::default()),
            ..Default::default()
        }
    }

    fn row(r: &StepRecord) -> String {
        let values: Vec<String> = csv_values(r).iter().map(f64::to_string).collect();
        values.join(",") + "\n"
    }

    #[test]
    fn a_restart_cuts_the_impact_rows_after_its_checkpoint_and_a_torn_row_and_keeps_the_header() {
        let dir = scratch("impacts");
        let path = dir.join("impacts.csv");
        let records: Vec<StepRecord> = [0.1, 0.2, 0.25, 0.3].map(record).to_vec();
        let mut text = format!("{}\n", header(true));
        records.iter().for_each(|r| text.push_str(&row(r)));
        let kept = text[..text.len() - row(&records[3]).len()].to_string();
        std::fs::write(&path, &text).unwrap();
        let (back, cut) = impacts_until(&path, 0.25).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text, "cut only when applied");
        cut.apply().unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), kept);
        let times: Vec<f64> = back.iter().map(|r| r.time).collect();
        assert_eq!(times, [0.1, 0.2, 0.25]);
        // a row cut short by a kill, its time read as 0.2, is no row
        std::fs::write(&path, format!("{kept}0.2")).unwrap();
        let (back, cut) = impacts_until(&path, 0.25).unwrap();
        assert_eq!(back.len(), 3);
        cut.apply().unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), kept);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_restart_cuts_events_csv_after_the_checkpoints_events_and_refuses_another_runs() {
        let dir = scratch("events");
        let path = dir.join("events.csv");
        let event = |time, kind| ContactEvent {
            time,
            kind,
            theta: -0.0,
            omega: -1.5,
            impulse: 0.0,
            penetration: 0.0,
            force: 0.0,
        };
        let events = [
            event(0.24, ContactEventKind::Start),
            event(0.26, ContactEventKind::End),
            event(0.72, ContactEventKind::Start),
        ];
        let mut text = format!("{}\n", crate::rows::EVENTS_HEADER);
        events.iter().for_each(|e| text.push_str(&(event_row(e) + "\n")));
        std::fs::write(&path, &text).unwrap();
        // the checkpoint was taken after the first two events; the start of an impact that began
        // with a touch before it is in the file too
        events_until(&path, &events[..2]).unwrap().apply().unwrap();
        let kept = std::fs::read_to_string(&path).unwrap();
        assert_eq!(kept.lines().count(), 3, "{kept}");
        assert!(text.starts_with(&kept));
        assert!(
            events_until(&path, &events[..2]).is_ok(),
            "nothing after them: nothing to cut"
        );
        let e = events_until(&path, &events).unwrap_err().to_string();
        assert!(e.contains("2 events, but the checkpoint has 3"), "{e}");
        let e = events_until(&path, &[events[1]]).unwrap_err().to_string();
        assert!(e.contains("events.csv:2:") && e.contains("does not belong"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
