//! The reduced body's set-up, kept so that it is computed once: in memory for the process (a
//! second `Simulation` or FMU instance of the same body takes a copy) and on disk across processes
//! (a second run, a sweep's cases, an FMU in another importer).
//!
//! **The key** is a hash of everything the body depends on and nothing else: the mesh (the model
//! fingerprint's mesh part), the configuration's `[geometry]`, `[mesh]` (less the file's path),
//! `[material]`, `[model]`, `[wall]` and `[contact]` sections, whether the model has a torque term,
//! and the core's source code (`PENDULUM_FEM_SOURCE_HASH`, made by the build script from every
//! file of `src/`): gravity, the start, the time step, the torque's profile and size and the
//! solver do not enter the basis, so a sweep over them shares one body, and a build with other
//! code never reads another build's file. A torque term adds its entries to the sparsity pattern
//! the set-up is computed on, which changes the fill-reducing ordering and so the set-up's
//! rounding (1e-14 relative): with the term's presence in the key, a run's results never depend
//! on which run filled the cache.
//!
//! **On disk** in the cache folder ([`crate::store::cache_folder`]): one file `reduced-<key>.bin` per body,
//! the body's values as IEEE bits behind a magic, the format version and the key, with a trailing
//! checksum ([`format`]). A file that does not read back whole (damaged, truncated, another key)
//! is rebuilt and replaced; a folder that cannot be written costs the set-up, nothing else. A file
//! is written under a temporary name and renamed, so parallel cases never read half of one, and on
//! a thread of its own while the run that computed the body steps (its model waits for it when
//! dropped, [`PendingWrite`]). The body read back is the one computed, bit for bit.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, OnceLock};

use super::ReducedBody;
use crate::error::Error;
use crate::model::Model;
use crate::store::{cache_folder, fnv1a, write_bytes_atomically};

mod format;

pub use format::{from_bytes, from_file, to_bytes};

/// Version of the cache file's format (2: the checksum in four lanes, [`format`]).
pub const CACHE_VERSION: u32 = 2;

/// The cache key of the reduced body of `model` (see the module doc).
pub fn key(model: &Model) -> u64 {
    key_of(&model.config, model.fingerprint.mesh, model.torque.is_some())
}

/// The cache key of the reduced body of a model of `config` on the mesh with the fingerprint
/// `mesh`, with a torque term or without: [`key`] before the model is made.
pub fn key_of(config: &crate::config::Config, mesh: u64, torque: bool) -> u64 {
    let mut json = serde_json::to_value(config).unwrap_or(serde_json::Value::Null);
    let mut kept = serde_json::Map::new();
    if let Some(obj) = json.as_object_mut() {
        if let Some(mesh) = obj.get_mut("mesh").and_then(|m| m.as_object_mut()) {
            mesh.remove("file");
        }
        for section in ["geometry", "mesh", "material", "model", "wall", "contact"] {
            if let Some(v) = obj.remove(section) {
                kept.insert(section.to_string(), v);
            }
        }
    }
    let text = format!(
        "{CACHE_VERSION}/{}/{:016x}/torque term {}/{}",
        env!("PENDULUM_FEM_SOURCE_HASH"),
        mesh,
        torque,
        serde_json::Value::Object(kept)
    );
    fnv1a(text.as_bytes())
}

/// Runs `f` with the disk cache in `dir` (`None`: off) and this process's memory of bodies emptied
/// first, as a fresh process with `PENDULUM_FEM_CACHE = dir` would (`pendulum-fem bench reduced`
/// times a set-up from nothing this way).
pub fn with_folder<R>(dir: Option<PathBuf>, f: impl FnOnce() -> R) -> R {
    if let Ok(mut m) = memory().lock() {
        m.clear();
    }
    crate::store::files::with_cache_folder(dir, f)
}

/// The file of the body with `key` in `dir`.
pub fn file(dir: &std::path::Path, key: u64) -> PathBuf {
    dir.join(format!("reduced-{key:016x}.bin"))
}

/// The bodies computed in this process, by key.
fn memory() -> &'static Mutex<HashMap<u64, Arc<ReducedBody>>> {
    static BODIES: OnceLock<Mutex<HashMap<u64, Arc<ReducedBody>>>> = OnceLock::new();
    BODIES.get_or_init(Default::default)
}

/// The reduced body of `model`: from this process's memory, from the disk, or computed by `build`
/// (and then kept in both, the file written as [`build_and_keep`] says). The models of one process
/// share one body (it is read only).
pub fn load_or_build(
    model: &Model,
    build: impl FnOnce() -> Result<ReducedBody, Error>,
) -> Result<(Arc<ReducedBody>, PendingWrite), Error> {
    let key = key(model);
    match stored(key) {
        Some(body) => Ok((body, PendingWrite::default())),
        None => build_and_keep(key, build),
    }
}

/// The body with `key` from this process's memory or from the disk (then kept in memory), if
/// either has it.
pub fn stored(key: u64) -> Option<Arc<ReducedBody>> {
    if let Some(body) = memory().lock().ok().and_then(|m| m.get(&key).cloned()) {
        return Some(body);
    }
    let body = Arc::new(from_file(&file(&cache_folder()?, key), key).ok()?);
    if let Ok(mut m) = memory().lock() {
        m.insert(key, body.clone());
    }
    Some(body)
}

/// A cache file being written on a thread of its own. Dropping it waits for the write to end: the
/// model that holds it ([`Model`]) lives as long as its run, so a run that ends has left the whole
/// file (or, if the folder cannot be written, none).
#[derive(Debug, Default)]
pub struct PendingWrite(Option<std::thread::JoinHandle<()>>);

impl Drop for PendingWrite {
    fn drop(&mut self) {
        if let Some(writer) = self.0.take() {
            let _ = writer.join();
        }
    }
}

/// The body with `key` computed by `build`, kept in memory and on the disk. The file (3.5 MB for
/// the tutorial's body, a few milliseconds to encode and write) is written on a thread of its own
/// while the caller goes on to its steps; the returned [`PendingWrite`] waits for it when dropped.
pub fn build_and_keep(
    key: u64,
    build: impl FnOnce() -> Result<ReducedBody, Error>,
) -> Result<(Arc<ReducedBody>, PendingWrite), Error> {
    let body = Arc::new(build()?);
    if let Ok(mut m) = memory().lock() {
        m.insert(key, body.clone());
    }
    let write = cache_folder().map(|dir| {
        let (path, kept) = (file(&dir, key), body.clone());
        // a cache that cannot be written costs the next run its set-up, nothing else; a thread
        // that cannot be started leaves the file unwritten
        std::thread::Builder::new()
            .name("reduced-cache-write".into())
            .spawn(move || {
                let _ = write_bytes_atomically(&path, &to_bytes(&kept, key));
            })
            .ok()
    });
    Ok((body, PendingWrite(write.flatten())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{Config, ModelKind, WallKind};

    fn model(cfg: &Config) -> Model {
        Model::new(cfg, crate::mesh::generate(cfg).unwrap()).unwrap()
    }

    #[test]
    fn a_cached_body_reads_back_bit_for_bit_and_a_damaged_file_is_refused() {
        let mut cfg = Config::default();
        cfg.model.kind = ModelKind::Reduced;
        cfg.wall.kind = WallKind::Rigid;
        let m = model(&cfg);
        let body = crate::reduced::basis::for_model(&m).unwrap();
        let k = key(&m);
        let bytes = to_bytes(&body, k);
        assert_eq!(from_bytes(&bytes, k).unwrap(), body);
        assert!(from_bytes(&bytes, k ^ 1).is_err(), "another key");
        let mut damaged = bytes.clone();
        damaged[bytes.len() / 2] ^= 0x10;
        assert!(from_bytes(&damaged, k).is_err(), "a flipped bit");
        assert!(from_bytes(&bytes[..bytes.len() - 9], k).is_err(), "truncated");
        // the file read streams the same bytes
        let dir = std::env::temp_dir().join(format!("pendulum-fem-cache-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = file(&dir, k);
        std::fs::write(&path, &bytes).unwrap();
        assert_eq!(from_file(&path, k).unwrap(), body);
        std::fs::write(&path, &damaged).unwrap();
        assert!(from_file(&path, k).is_err(), "a flipped bit on disk");
        std::fs::write(&path, &bytes[..bytes.len() - 1]).unwrap();
        assert!(from_file(&path, k).is_err(), "a truncated file");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn the_key_follows_the_body_and_ignores_the_start_the_step_and_gravity() {
        let mut cfg = Config::default();
        cfg.model.kind = ModelKind::Reduced;
        let base = key(&model(&cfg));
        let mut other = cfg.clone();
        other.initial.angle_deg = 40.0;
        other.time.dt = 0.001;
        other.gravity.g = 3.0;
        assert_eq!(key(&model(&other)), base);
        for change in [
            |c: &mut Config| c.material.youngs_modulus = 1e9,
            |c: &mut Config| c.model.modes = 4,
            |c: &mut Config| c.mesh.refine = 1.5,
        ] {
            let mut c = cfg.clone();
            change(&mut c);
            assert_ne!(key(&model(&c)), base);
        }
    }
}
