//! Generated meshes kept on disk, in the cache folder
//! ([`crate::store::cache_folder`]): a run of a pendulum meshed before (a second run, a job
//! array's or a process sweep's cases, an FMU instantiated again) reads its mesh instead of meshing.
//!
//! **The key** is a hash of what a generated mesh depends on: the configuration's `[geometry]` and
//! `[mesh]` sections, the file format's version and the core's source code
//! (`PENDULUM_FEM_SOURCE_HASH`), so a build with another mesher never reads another build's mesh.
//! A mesh read from `mesh.file` is not kept (the file may change).
//!
//! **The file** `mesh-<key>.bin`: the magic `PFEMMESH`, the version, the key, the mesh's counts,
//! coordinates (the bits of `f64`), connectivity and names, all little-endian, and an FNV-1a
//! checksum of every byte before it. A file that does not read back whole (damaged, truncated,
//! another key, an index out of range) is meshed anew and replaced; a folder that cannot be
//! written costs the meshing, nothing else. Files are written under a temporary name and renamed.
//! The mesh read back equals the generated one exactly (`Mesh: PartialEq`), so a run's results do
//! not depend on whether its mesh was read or made.

use std::path::{Path, PathBuf};

use super::{BoundaryEdge, Mesh};
use crate::config::Config;
use crate::error::Error;
use crate::store::bytes::{Reader, Writer};
use crate::store::{cache_folder, fnv1a, write_bytes_atomically};

const MAGIC: &[u8; 8] = b"PFEMMESH";

/// Version of the file's format.
const VERSION: u32 = 1;

/// The key of the mesh that `config` generates (see the module doc). The sections are hashed in
/// their `Debug` form, which writes every number so that it reads back exactly, and tells an
/// infinite or NaN value from an absent one (JSON writes all three as `null`: a hinge edge size
/// of `+∞`, which the mesher refuses, had the key of the default size).
pub fn key(config: &Config) -> u64 {
    let text = format!(
        "mesh/{VERSION}/{}/{:?}/{:?}",
        env!("PENDULUM_FEM_SOURCE_HASH"),
        config.geometry,
        config.mesh
    );
    fnv1a(text.as_bytes())
}

/// The file of the mesh with `key` in `dir`.
pub fn file(dir: &Path, key: u64) -> PathBuf {
    dir.join(format!("mesh-{key:016x}.bin"))
}

/// The mesh of `config` from the disk, if a whole file of it is there.
pub(super) fn load(config: &Config) -> Option<Mesh> {
    let key = key(config);
    let path = file(&cache_folder()?, key);
    let bytes = std::fs::read(&path).ok()?;
    from_bytes(&bytes, key, &path.display().to_string()).ok()
}

/// Writes `mesh`, generated from `config`, to the disk (nothing where there is no folder or it
/// cannot be written).
pub(super) fn store(config: &Config, mesh: &Mesh) {
    if let Some(dir) = cache_folder() {
        let key = key(config);
        let _ = write_bytes_atomically(&file(&dir, key), &to_bytes(mesh, key));
    }
}

fn string(w: &mut Writer, s: &str) {
    w.usize(s.len());
    w.0.extend_from_slice(s.as_bytes());
}

/// The mesh as the file's bytes (see the module doc).
pub fn to_bytes(mesh: &Mesh, key: u64) -> Vec<u8> {
    let mut w = Writer(Vec::new());
    w.0.extend_from_slice(MAGIC);
    w.u32(VERSION);
    w.u64(key);
    w.u32(mesh.order);
    w.usize(mesh.num_vertices);
    w.vec(&mesh.nodes.iter().flatten().copied().collect::<Vec<f64>>());
    w.usize(mesh.triangles.len());
    mesh.triangles.iter().flatten().for_each(|&n| w.usize(n));
    w.usize(mesh.boundary_edges.len());
    for e in &mesh.boundary_edges {
        e.nodes.iter().for_each(|&n| w.usize(n));
        w.usize(e.name);
        w.usize(e.triangle);
        w.usize(e.local_edge);
    }
    w.usize(mesh.boundary_names.len());
    mesh.boundary_names.iter().for_each(|s| string(&mut w, s));
    string(&mut w, &mesh.region_name);
    let sum = fnv1a(&w.0);
    w.u64(sum);
    w.0
}

/// Reads [`to_bytes`]'s bytes of the mesh with `key` (`source` names them in errors); anything
/// else, or a mesh whose indices fall outside it, is an error.
pub fn from_bytes(bytes: &[u8], key: u64, source: &str) -> Result<Mesh, Error> {
    let bad = |why: &str| Error::Input(format!("{source}: not a mesh cache file of this build ({why})"));
    let body = bytes.len().checked_sub(8).ok_or_else(|| bad("too short"))?;
    let stored = u64::from_le_bytes(bytes[body..].try_into().expect("8 bytes"));
    if fnv1a(&bytes[..body]) != stored {
        return Err(bad("checksum"));
    }
    let mut r = Reader {
        bytes: &bytes[..body],
        pos: 0,
        source,
    };
    if r.take(8, "magic")? != MAGIC {
        return Err(bad("magic"));
    }
    let version = r.u32("version")?;
    if version != VERSION || r.u64("key")? != key {
        return Err(bad("another version or mesh"));
    }
    let order = r.u32("order")?;
    let num_vertices = r.usize("vertices")?;
    let nodes: Vec<[f64; 2]> = r.vec("nodes")?.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
    let node = |r: &mut Reader, what: &str| -> Result<usize, Error> {
        let n = r.usize(what)?;
        if n < nodes.len() {
            Ok(n)
        } else {
            Err(bad("a node index out of range"))
        }
    };
    let triangles = (0..r.count("triangles", 6 * 8)?)
        .map(|_| {
            let mut t = [0; 6];
            for n in &mut t {
                *n = node(&mut r, "triangle")?;
            }
            Ok(t)
        })
        .collect::<Result<Vec<[usize; 6]>, Error>>()?;
    let boundary_edges = (0..r.count("boundary edges", 6 * 8)?)
        .map(|_| {
            let nodes = [node(&mut r, "edge")?, node(&mut r, "edge")?, node(&mut r, "edge")?];
            let (name, triangle, local_edge) = (r.usize("edge")?, r.usize("edge")?, r.usize("edge")?);
            if triangle >= triangles.len() || local_edge > 2 {
                return Err(bad("an edge's triangle out of range"));
            }
            Ok(BoundaryEdge {
                nodes,
                name,
                triangle,
                local_edge,
            })
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let text = |r: &mut Reader| -> Result<String, Error> {
        let n = r.count("name", 1)?;
        String::from_utf8(r.take(n, "name")?.to_vec()).map_err(|_| bad("a name"))
    };
    let boundary_names = (0..r.count("names", 8)?)
        .map(|_| text(&mut r))
        .collect::<Result<Vec<_>, Error>>()?;
    let region_name = text(&mut r)?;
    if r.pos != r.bytes.len()
        || num_vertices > nodes.len()
        || boundary_edges.iter().any(|e| e.name >= boundary_names.len())
    {
        return Err(bad("inconsistent"));
    }
    Ok(Mesh {
        nodes,
        num_vertices,
        triangles,
        boundary_edges,
        boundary_names,
        region_name,
        order,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mesh read back is the generated one exactly, and every damaged file is refused: each
    /// byte flipped in turn (every 97th, and the last ones), truncated, another key.
    #[test]
    fn a_kept_mesh_reads_back_exactly_and_a_damaged_file_is_refused() {
        let cfg = Config::default();
        let mesh = super::super::generate_with_stats(&cfg).expect("mesh").0;
        let key = key(&cfg);
        let bytes = to_bytes(&mesh, key);
        assert_eq!(from_bytes(&bytes, key, "test").expect("reads back"), mesh);
        for i in (0..bytes.len()).step_by(97).chain(bytes.len() - 9..bytes.len()) {
            let mut damaged = bytes.clone();
            damaged[i] ^= 0x10;
            assert!(from_bytes(&damaged, key, "test").is_err(), "byte {i} flipped");
        }
        assert!(from_bytes(&bytes[..bytes.len() - 1], key, "test").is_err());
        assert!(from_bytes(&bytes, key ^ 1, "test").is_err());
        let mut other = cfg.clone();
        other.mesh.refine = 2.0;
        assert_ne!(super::key(&other), key, "the key follows the [mesh] section");
        // an infinite size is not the absent one (JSON writes both as null)
        let mut infinite = cfg.clone();
        infinite.mesh.hinge_edge_size = Some(f64::INFINITY);
        assert_ne!(super::key(&infinite), key);
    }
}
