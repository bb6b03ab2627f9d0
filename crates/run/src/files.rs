//! Files written whole or not at all: every file a run replaces (events, checkpoints, summaries,
//! ParaView frames) goes through [`write_atomically`], so a run stopped meanwhile leaves the
//! previous version intact and never a torn file.

use std::io::Write;
use std::path::Path;

use pendulum_fem_core::{Config, Error};

/// `cfg` as TOML that reads back to the same configuration from any folder: the input files
/// (`mesh.file`, `torque.file`) made absolute. `name` names the file in an error. One rule for a
/// checkpoint's configuration, a study case's and a pickled Python simulation's.
pub fn portable_toml(cfg: &Config, name: &str) -> Result<String, Error> {
    let mut cfg = cfg.clone();
    for file in [&mut cfg.mesh.file, &mut cfg.torque.file].into_iter().flatten() {
        if let Ok(abs) = std::path::absolute(&*file) {
            *file = abs;
        }
    }
    toml::to_string(&cfg).map_err(|e| Error::Input(format!("{name}: {e}")))
}

/// Writes what `fill` writes to `path` through a temporary file in the same folder, then renames it.
pub fn write_atomically(path: &Path, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<(), Error> {
    let tmp = path.with_extension(format!(
        "{}.partial",
        path.extension()
            .map(|e| e.to_string_lossy().into_owned())
            .unwrap_or_default()
    ));
    let result = (|| {
        let file = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::with_capacity(1 << 16, file);
        fill(&mut w)?;
        w.flush()?;
        drop(w);
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, e)
    })
}
