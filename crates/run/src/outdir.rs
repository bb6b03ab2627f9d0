//! Where a run (and `pendulum-fem modes`) writes: a fresh numbered folder per run, or one the user
//! names. What differs between the commands is in their [`Outputs`] ([`RUN_OUTPUTS`],
//! [`MODES_OUTPUTS`]); the rules are the same:
//!
//! - Without an explicit folder, every run gets `BASE/run-NNNN` (`BASE/modes-NNNN` for the modes)
//!   with the next free number (one more than the largest existing one of that prefix), created
//!   with `create_dir` and retried on a collision, so two runs started at once never share a
//!   folder. For runs, `BASE/latest` then points at it: a relative symbolic link on Unix, replaced
//!   atomically (link under a temporary name, then rename); where links cannot be made,
//!   `BASE/latest.txt` holds the folder name instead.
//! - An explicit folder (`--out`) is used as it is; if it exists and holds anything, the command is
//!   refused unless `force` is set, and the refusal changes nothing on disk. With `force`, every
//!   file the command writes (for a run [`RUN_FILES`], `frames/step_*.vtu` and unfinished
//!   `*.partial` files; for the modes [`MODES_FILES`] and `modes/mode_*.vtu`) is removed first, so
//!   no file of an earlier (say longer) run survives to mix with the new one; other files are left
//!   alone. Call [`Outputs::prepare`] ([`prepare_output_dir`] for a run) before any computing, so a
//!   refused command costs nothing.

use std::path::{Path, PathBuf};

use crate::Error;

/// File names inside the output folder.
pub mod names {
    /// The solver's time history, a row per step.
    pub const RESULTS_CSV: &str = "results.csv";
    /// The contact events of a run with a wall, a row per event as it happens.
    pub const EVENTS_CSV: &str = "events.csv";
    /// The records of the sub-steps inside impacts, the columns of `results.csv`.
    pub const IMPACTS_CSV: &str = "impacts.csv";
    /// θ(t) plot.
    pub const THETA_PNG: &str = "theta.png";
    /// Energy plot.
    pub const ENERGY_PNG: &str = "energy.png";
    /// Animation coloured by |u|.
    pub const DISPLACEMENT_GIF: &str = "displacement.gif";
    /// Animation coloured by von Mises stress.
    pub const VON_MISES_GIF: &str = "von_mises.gif";
    /// The HTML viewer.
    pub const VIEWER_HTML: &str = "viewer.html";
    /// The ParaView collection of the frames.
    pub const PVD_NAME: &str = "pendulum.pvd";
    /// The folder of the ParaView frames (`step_NNNNN.vtu`).
    pub const FRAMES_DIR: &str = "frames";
    /// The table of the modes, their checks and timings (`pendulum-fem modes`).
    pub const MODES_JSON: &str = "modes.json";
    /// The ParaView collection of the mode shapes.
    pub const MODES_PVD: &str = "modes.pvd";
    /// The picture of the first elastic modes.
    pub const MODES_PNG: &str = "modes.png";
    /// The folder of the mode shapes (`mode_NN.vtu`).
    pub const MODES_DIR: &str = "modes";
    /// The latest snapshot of a run with checkpoints ([`pendulum_fem_core::Snapshot::to_bytes`]).
    pub const CHECKPOINT_SNAP: &str = "checkpoint.snap";
    /// The configuration of a run with checkpoints, read by `run --restart`.
    pub const CHECKPOINT_TOML: &str = "checkpoint.toml";
}

/// Prefix of the numbered run folders.
pub const RUN_PREFIX: &str = "run-";
/// Prefix of the numbered folders of `pendulum-fem modes`.
pub const MODES_PREFIX: &str = "modes-";
/// Name of the pointer to the newest run folder.
pub const LATEST: &str = "latest";

/// Files a run may write at the top of its folder (besides `frames/`).
pub const RUN_FILES: [&str; 12] = [
    names::RESULTS_CSV,
    names::EVENTS_CSV,
    names::IMPACTS_CSV,
    names::CHECKPOINT_SNAP,
    names::CHECKPOINT_TOML,
    crate::status::STATUS_JSON,
    names::THETA_PNG,
    names::ENERGY_PNG,
    names::DISPLACEMENT_GIF,
    names::VON_MISES_GIF,
    names::VIEWER_HTML,
    names::PVD_NAME,
];

/// Files `pendulum-fem modes` writes at the top of its folder (besides `modes/`).
pub const MODES_FILES: [&str; 3] = [names::MODES_JSON, names::MODES_PVD, names::MODES_PNG];

/// What one command writes into its output folder: the names the rules of the module
/// documentation act on.
#[derive(Clone, Copy, Debug)]
pub struct Outputs {
    /// What the refusal of a non-empty folder calls an earlier use of it ("run").
    pub what: &'static str,
    /// Prefix of the numbered folders.
    pub prefix: &'static str,
    /// The files at the top of the folder.
    pub files: &'static [&'static str],
    /// The subfolder of one file per frame or mode, and the prefix and extension of those files.
    pub items: (&'static str, &'static str, &'static str),
    /// Whether `BASE/latest` points at the newest numbered folder.
    pub latest: bool,
}

/// What a run writes.
pub const RUN_OUTPUTS: Outputs = Outputs {
    what: "run",
    prefix: RUN_PREFIX,
    files: &RUN_FILES,
    items: (names::FRAMES_DIR, "step_", ".vtu"),
    latest: true,
};

/// What `pendulum-fem modes` writes.
pub const MODES_OUTPUTS: Outputs = Outputs {
    what: "modal analysis",
    prefix: MODES_PREFIX,
    files: &MODES_FILES,
    items: (names::MODES_DIR, "mode_", ".vtu"),
    latest: false,
};

/// Removes what a run writes from `dir` ([`RUN_OUTPUTS`]; see [`Outputs::clear`]).
pub fn clear_run_outputs(dir: &Path) -> Result<(), Error> {
    RUN_OUTPUTS.clear(dir)
}

/// The folder a run writes to ([`RUN_OUTPUTS`]; see [`Outputs::prepare`]).
pub fn prepare_output_dir(base: &Path, explicit: Option<&Path>, force: bool) -> Result<PathBuf, Error> {
    RUN_OUTPUTS.prepare(base, explicit, force)
}

impl Outputs {
    /// Removes what this command writes from `dir` (see the module documentation); the items'
    /// subfolder goes too when nothing else is left in it.
    pub fn clear(&self, dir: &Path) -> Result<(), Error> {
        let remove = |path: &Path| match std::fs::remove_file(path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(Error::io(path, e)),
            _ => Ok(()),
        };
        let is_own_file = |name: &str| {
            self.files
                .iter()
                .any(|f| name == *f || name.starts_with(&format!("{f}.")))
        };
        for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
            let entry = entry.map_err(|e| Error::io(dir, e))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            if self.files.contains(&name.as_str()) || (is_own_file(&name) && name.ends_with(".partial")) {
                remove(&entry.path())?;
            }
        }
        let (folder, prefix, ext) = self.items;
        let items = dir.join(folder);
        if items.is_dir() {
            for entry in std::fs::read_dir(&items).map_err(|e| Error::io(&items, e))? {
                let entry = entry.map_err(|e| Error::io(&items, e))?;
                let name = entry.file_name().to_string_lossy().into_owned();
                if name.starts_with(prefix) && (name.ends_with(ext) || name.ends_with(".partial")) {
                    remove(&entry.path())?;
                }
            }
            let _ = std::fs::remove_dir(&items); // only if empty
        }
        Ok(())
    }

    /// Returns the folder this command writes to, created and empty (unless `force` let an
    /// explicit, non-empty one through). See the module documentation for the rules.
    pub fn prepare(&self, base: &Path, explicit: Option<&Path>, force: bool) -> Result<PathBuf, Error> {
        match explicit {
            Some(dir) => self.prepare_explicit(dir, force),
            None => {
                let dir = create_numbered(base, self.prefix)?;
                if self.latest {
                    update_latest(base, &dir);
                }
                Ok(dir)
            }
        }
    }

    fn prepare_explicit(&self, dir: &Path, force: bool) -> Result<PathBuf, Error> {
        match std::fs::metadata(dir) {
            Ok(m) if !m.is_dir() => Err(Error::Config(format!(
                "--out {}: exists and is not a folder; name a folder (new or empty)",
                dir.display()
            ))),
            Ok(_) => {
                let mut entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
                if entries.next().is_some() && !force {
                    return Err(Error::Config(format!(
                        "--out {}: the folder is not empty; refusing to write into it (nothing was changed). \
                         Pass --force to write there anyway (the outputs of an earlier {} are removed first, \
                         other files are kept), or choose another folder",
                        dir.display(),
                        self.what
                    )));
                }
                if force {
                    self.clear(dir)?;
                }
                Ok(dir.to_path_buf())
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
                Ok(dir.to_path_buf())
            }
            Err(e) => Err(Error::io(dir, e)),
        }
    }
}

/// Number of a numbered folder's name (`run-0007` with the prefix `run-`).
fn folder_number(name: &str, prefix: &str) -> Option<u64> {
    name.strip_prefix(prefix)
        .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))?
        .parse()
        .ok()
}

fn create_numbered(base: &Path, prefix: &str) -> Result<PathBuf, Error> {
    std::fs::create_dir_all(base).map_err(|e| Error::io(base, e))?;
    let mut next = std::fs::read_dir(base)
        .map_err(|e| Error::io(base, e))?
        .filter_map(|e| e.ok())
        .filter_map(|e| folder_number(&e.file_name().to_string_lossy(), prefix))
        .max()
        .map_or(1, |n| n + 1);
    for _ in 0..10_000 {
        let dir = base.join(format!("{prefix}{next:04}"));
        match std::fs::create_dir(&dir) {
            Ok(()) => return Ok(dir),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => next += 1,
            Err(e) => return Err(Error::io(&dir, e)),
        }
    }
    Err(Error::io(
        base,
        std::io::Error::other(format!(
            "could not create a fresh {prefix}NNNN folder after 10000 tries"
        )),
    ))
}

/// Points `base/latest` at `dir` (best effort: a failure here never fails the run).
fn update_latest(base: &Path, dir: &Path) {
    let name = dir.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    #[cfg(unix)]
    {
        let tmp = base.join(format!(".{LATEST}.{}.tmp", std::process::id()));
        let _ = std::fs::remove_file(&tmp);
        if std::os::unix::fs::symlink(&name, &tmp).is_ok() && std::fs::rename(&tmp, base.join(LATEST)).is_ok() {
            let _ = std::fs::remove_file(base.join(format!("{LATEST}.txt")));
            return;
        }
        let _ = std::fs::remove_file(&tmp);
    }
    let _ = pendulum_fem_core::store::write_atomically(&base.join(format!("{LATEST}.txt")), |w| {
        writeln!(w, "{}", name.to_string_lossy())
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folder_numbers_parse_only_the_folders_of_their_prefix() {
        assert_eq!(folder_number("run-0007", RUN_PREFIX), Some(7));
        assert_eq!(folder_number("run-12345", RUN_PREFIX), Some(12345));
        assert_eq!(folder_number("run-", RUN_PREFIX), None);
        assert_eq!(folder_number("run-1a", RUN_PREFIX), None);
        assert_eq!(folder_number("latest", RUN_PREFIX), None);
        assert_eq!(folder_number("modes-0003", RUN_PREFIX), None);
        assert_eq!(folder_number("modes-0003", MODES_PREFIX), Some(3));
    }

    #[test]
    fn forced_runs_clear_the_partial_files_of_the_cores_atomic_writes_and_keep_other_files() {
        let dir = std::env::temp_dir().join(format!("pendulum-fem-clear-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join(names::FRAMES_DIR)).unwrap();
        // the names pendulum_fem_core::store::write_atomically gives its temporary files
        let pid = std::process::id();
        let run_files = [
            format!("{}.{pid}-0-123456789.partial", names::EVENTS_CSV),
            format!("{}.{pid}-3-42.partial", names::PVD_NAME),
            format!("{}/step_00010.vtu.{pid}-7-1.partial", names::FRAMES_DIR),
            names::RESULTS_CSV.to_string(),
        ];
        let kept = ["notes.txt", "notes.txt.1-2-3.partial"];
        for name in run_files.iter().map(String::as_str).chain(kept) {
            std::fs::write(dir.join(name), b"x").unwrap();
        }
        clear_run_outputs(&dir).unwrap();
        let mut left: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(
            left, kept,
            "only the files no run writes are left (frames/ emptied and removed)"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
