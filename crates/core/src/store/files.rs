//! Files written whole or not at all, and the cache folder.
//!
//! [`write_atomically`] writes into a temporary file beside the target, named after it with a
//! suffix unique to the process, the writer and the moment and ending in `.partial`, and renames it
//! over the target: a reader (another process, a parallel case writing the same cache file) sees
//! the previous file or the new one, never a torn one, and a run stopped meanwhile leaves at most
//! a `.partial` file behind.
//!
//! The cache folder ([`cache_folder`]) holds what is computed once and kept across processes (the
//! reduced bodies, generated meshes): `$PENDULUM_FEM_CACHE` if set (`off` turns the disk cache
//! off), else `$XDG_CACHE_HOME/pendulum-fem` or `~/.cache/pendulum-fem`.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use crate::error::Error;

/// Writes what `fill` writes to `path` through a temporary file in the same folder (made if
/// missing), then renames it over `path` (see the module doc). Errors name `path`.
pub fn write_atomically(path: &Path, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<(), Error> {
    static WRITES: AtomicU64 = AtomicU64::new(0);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let partial = path.with_file_name(format!(
        "{name}.{}-{}-{nanos}.partial",
        std::process::id(),
        WRITES.fetch_add(1, Ordering::Relaxed)
    ));
    let result = (|| {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        let file = std::fs::File::create(&partial)?;
        let mut w = std::io::BufWriter::with_capacity(1 << 16, file);
        fill(&mut w)?;
        w.flush()?;
        drop(w);
        std::fs::rename(&partial, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&partial);
        Error::io(path, e)
    })
}

/// [`write_atomically`] of `bytes`.
pub fn write_bytes_atomically(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    write_atomically(path, |w| w.write_all(bytes))
}

/// A folder that [`cache_folder`] answers instead of the environment's ([`with_cache_folder`]).
static FOLDER: Mutex<Option<Option<PathBuf>>> = Mutex::new(None);

/// Runs `f` with the cache folder `dir` (`None`: off), as a process with `PENDULUM_FEM_CACHE = dir`
/// would see it.
pub fn with_cache_folder<R>(dir: Option<PathBuf>, f: impl FnOnce() -> R) -> R {
    let before = FOLDER.lock().map(|mut g| g.replace(dir)).unwrap_or(None);
    let out = f();
    if let Ok(mut g) = FOLDER.lock() {
        *g = before;
    }
    out
}

/// The cache folder on disk, `None` when turned off (see the module doc).
pub fn cache_folder() -> Option<PathBuf> {
    if let Some(dir) = FOLDER.lock().ok().and_then(|g| g.clone()) {
        return dir;
    }
    match std::env::var_os("PENDULUM_FEM_CACHE") {
        Some(v) if v == "off" => None,
        Some(v) if !v.is_empty() => Some(PathBuf::from(v)),
        _ => std::env::var_os("XDG_CACHE_HOME")
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
            .map(|d| d.join("pendulum-fem")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_previous_file_and_no_partial_file() {
        let dir = std::env::temp_dir().join(format!("pendulum-fem-atomic-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let path = dir.join("events.csv");
        write_bytes_atomically(&path, b"first\n").unwrap();
        let e = write_atomically(&path, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("stopped"))
        })
        .unwrap_err();
        assert!(e.to_string().contains("events.csv"), "{e}");
        assert_eq!(std::fs::read(&path).unwrap(), b"first\n");
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["events.csv"], "no .partial file left");
        write_bytes_atomically(&path, b"second\n").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"second\n");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
