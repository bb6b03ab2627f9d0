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
//! **On disk** in `$PENDULUM_FEM_CACHE` if set (`off` turns the disk off), else
//! `$XDG_CACHE_HOME/pendulum-fem` or `~/.cache/pendulum-fem`: one file `reduced-<key>.bin` per body,
//! the body's values as IEEE bits behind a magic, the format version and the key, with a trailing
//! checksum. A file that does not read back whole (damaged, truncated, another key) is rebuilt and
//! replaced; a folder that cannot be written costs the set-up, nothing else. A file is written under
//! a temporary name and renamed, so parallel cases never read half of one. The body read back is
//! the one computed, bit for bit.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, OnceLock};

use super::{ArcPoint, ProxyModes, ReducedBody, StressModes};
use crate::simulation::snapshot::bytes::{Reader, Writer};
use crate::simulation::snapshot::fnv::fnv1a;

/// The cache file's checksum: FNV-1a's step over little-endian 8-byte words (and the tail's
/// bytes), eight times fewer multiplications than over bytes for the file's few megabytes.
fn checksum(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let words = bytes.chunks_exact(8);
    let tail = words.remainder();
    for w in words {
        h = (h ^ u64::from_le_bytes(w.try_into().expect("8 bytes"))).wrapping_mul(0x0000_0100_0000_01b3);
    }
    for &b in tail {
        h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}
use crate::simulation::Model;
use crate::Error;

/// Version of the cache file's format.
pub const CACHE_VERSION: u32 = 1;

const MAGIC: &[u8; 8] = b"PFEMREDU";

/// The cache key of the reduced body of `model` (see the module doc).
pub fn key(model: &Model) -> u64 {
    let mut json = serde_json::to_value(&model.config).unwrap_or(serde_json::Value::Null);
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
        model.fingerprint.mesh,
        model.torque.is_some(),
        serde_json::Value::Object(kept)
    );
    fnv1a(text.as_bytes())
}

/// A folder that [`folder`] answers instead of the environment's, for [`with_folder`].
static FOLDER: Mutex<Option<Option<PathBuf>>> = Mutex::new(None);

/// Runs `f` with the disk cache in `dir` (`None`: off) and this process's memory of bodies emptied
/// first, as a fresh process with `PENDULUM_FEM_CACHE = dir` would (`pendulum-fem bench reduced`
/// times a set-up from nothing this way).
pub fn with_folder<R>(dir: Option<PathBuf>, f: impl FnOnce() -> R) -> R {
    if let Ok(mut m) = memory().lock() {
        m.clear();
    }
    let before = FOLDER.lock().map(|mut g| g.replace(dir)).unwrap_or(None);
    let out = f();
    if let Ok(mut g) = FOLDER.lock() {
        *g = before;
    }
    out
}

/// The cache folder on disk, `None` when turned off (see the module doc).
pub fn folder() -> Option<PathBuf> {
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
/// (and then kept in both). The models of one process share one body (it is read only).
pub fn load_or_build(
    model: &Model,
    build: impl FnOnce() -> Result<ReducedBody, Error>,
) -> Result<Arc<ReducedBody>, Error> {
    let key = key(model);
    if let Some(body) = memory().lock().ok().and_then(|m| m.get(&key).cloned()) {
        return Ok(body);
    }
    let path = folder().map(|d| file(&d, key));
    let read = path
        .as_ref()
        .and_then(|p| std::fs::read(p).ok())
        .and_then(|bytes| from_bytes(&bytes, key).ok());
    let body = match read {
        Some(body) => body,
        None => {
            let body = build()?;
            if let Some(p) = &path {
                // a cache that cannot be written costs the next run its set-up, nothing else
                let _ = write_atomically(p, &to_bytes(&body, key));
            }
            body
        }
    };
    let body = Arc::new(body);
    if let Ok(mut m) = memory().lock() {
        m.insert(key, body.clone());
    }
    Ok(body)
}

fn write_atomically(path: &std::path::Path, bytes: &[u8]) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let partial = path.with_extension(format!(
        "{}-{:?}-{nanos}.partial",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::write(&partial, bytes)?;
    std::fs::rename(&partial, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&partial);
    })
}

fn write_vecs(w: &mut Writer, vs: &[Vec<f64>]) {
    w.usize(vs.len());
    vs.iter().for_each(|v| w.vec(v));
}

fn read_vecs(r: &mut Reader, what: &str) -> Result<Vec<Vec<f64>>, Error> {
    let n = r.usize(what)?;
    if n > r.bytes.len() - r.pos {
        return Err(Error::Input(format!("{}: {what}: {n} vectors", r.source)));
    }
    (0..n).map(|_| r.vec(what)).collect()
}

/// The body as the cache file's bytes (format in the module doc).
pub fn to_bytes(b: &ReducedBody, key: u64) -> Vec<u8> {
    let mut w = Writer(Vec::new());
    w.0.extend_from_slice(MAGIC);
    w.u32(CACHE_VERSION);
    w.u64(key);
    write_vecs(&mut w, &b.shapes);
    for v in [&b.stiffness, &b.b, &b.d, &b.hub, &b.g] {
        w.vec(v);
    }
    w.f64(b.inertia);
    w.f64(b.s0[0]);
    w.f64(b.s0[1]);
    write_vecs(&mut w, &b.s);
    w.f64(b.mass);
    w.usize(b.arc.len());
    for p in &b.arc {
        w.f64(p.reference[0]);
        w.f64(p.reference[1]);
        write_vecs(&mut w, &p.modes);
        w.f64(p.weight);
        w.f64(p.bound);
    }
    w.vec(&b.reference);
    w.f64(b.proxy.polar);
    w.vec(&b.proxy.cos);
    w.vec(&b.proxy.sin);
    w.vec(&b.stress.values);
    w.usize(b.stress.nodes.len());
    b.stress.nodes.iter().for_each(|&n| w.usize(n));
    w.vec(&b.stress.counts);
    let sum = checksum(&w.0);
    w.u64(sum);
    w.0
}

/// Reads [`to_bytes`]'s bytes of the body with `key`; anything else is an error.
pub fn from_bytes(bytes: &[u8], key: u64) -> Result<ReducedBody, Error> {
    let bad = |why: &str| Error::Input(format!("reduced body cache: {why}"));
    if bytes.len() < 8 + 4 + 8 + 8 || &bytes[..8] != MAGIC {
        return Err(bad("not a cache file"));
    }
    let (body, sum) = bytes.split_at(bytes.len() - 8);
    if checksum(body) != u64::from_le_bytes(sum.try_into().expect("8 bytes")) {
        return Err(bad("damaged (checksum)"));
    }
    let mut r = Reader {
        bytes: body,
        pos: 8,
        source: "reduced body cache",
    };
    let version = u32::from_le_bytes(r.take(4, "version")?.try_into().expect("4 bytes"));
    if version != CACHE_VERSION || r.u64("key")? != key {
        return Err(bad("another version or body"));
    }
    let shapes = read_vecs(&mut r, "shapes")?;
    let [stiffness, b, d, hub, g] = [(); 5].map(|_| r.vec("operators"));
    let (stiffness, b, d, hub, g) = (stiffness?, b?, d?, hub?, g?);
    let inertia = r.f64("inertia")?;
    let s0 = [r.f64("s0")?, r.f64("s0")?];
    let s: [Vec<f64>; 2] = read_vecs(&mut r, "s")?.try_into().map_err(|_| bad("s"))?;
    let mass = r.f64("mass")?;
    let count = r.usize("arc")?;
    if count > r.bytes.len() - r.pos {
        return Err(bad("arc"));
    }
    let mut arc = Vec::with_capacity(count);
    for _ in 0..count {
        let reference = [r.f64("arc")?, r.f64("arc")?];
        let modes: [Vec<f64>; 2] = read_vecs(&mut r, "arc")?.try_into().map_err(|_| bad("arc modes"))?;
        let weight = r.f64("arc")?;
        let bound = r.f64("arc")?;
        arc.push(ArcPoint {
            reference,
            modes,
            weight,
            bound,
        });
    }
    let reference = r.vec("reference")?;
    let proxy = ProxyModes {
        polar: r.f64("proxy")?,
        cos: r.vec("proxy")?,
        sin: r.vec("proxy")?,
    };
    let values = r.vec("stress")?;
    let n = r.usize("stress nodes")?;
    if n > r.bytes.len() - r.pos {
        return Err(bad("stress nodes"));
    }
    let nodes = (0..n).map(|_| r.usize("stress nodes")).collect::<Result<Vec<_>, _>>()?;
    let counts = r.vec("stress counts")?;
    if r.pos != r.bytes.len() {
        return Err(bad("trailing bytes"));
    }
    let body = ReducedBody {
        shapes,
        stiffness,
        inertia,
        b,
        d,
        hub,
        g,
        s0,
        s,
        mass,
        arc,
        reference,
        proxy,
        stress: StressModes {
            values,
            nodes,
            counts,
            ..Default::default()
        },
    };
    let n = body.modes();
    let consistent = body.shapes.iter().all(|p| p.len() == body.reference.len())
        && [
            &body.b,
            &body.d,
            &body.hub,
            &body.s[0],
            &body.s[1],
            &body.proxy.cos,
            &body.proxy.sin,
        ]
        .iter()
        .all(|v| v.len() == n)
        && body.g.len() == n * n
        && body.arc.iter().all(|p| p.modes[0].len() == n && p.modes[1].len() == n)
        && body.stress.values.len() == body.stress.nodes.len() * 4 * n
        && body.stress.nodes.iter().all(|&k| k < body.stress.counts.len());
    if !consistent {
        return Err(bad("inconsistent sizes"));
    }
    Ok(body)
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
        let body = m.reduced.clone().unwrap();
        let k = key(&m);
        let bytes = to_bytes(&body, k);
        assert_eq!(from_bytes(&bytes, k).unwrap(), *body);
        assert!(from_bytes(&bytes, k ^ 1).is_err(), "another key");
        let mut damaged = bytes.clone();
        damaged[bytes.len() / 2] ^= 0x10;
        assert!(from_bytes(&damaged, k).is_err(), "a flipped bit");
        assert!(from_bytes(&bytes[..bytes.len() - 9], k).is_err(), "truncated");
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
