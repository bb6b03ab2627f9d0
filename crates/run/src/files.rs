//! Files written whole or not at all: every file a run replaces (events, checkpoints, summaries,
//! ParaView frames) goes through [`write_atomically`], so a run stopped meanwhile leaves the
//! previous version intact and never a torn file.

use std::io::Write;
use std::path::Path;

use pendulum_fem_core::Error;

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
