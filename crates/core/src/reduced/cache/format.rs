//! The cache file's bytes: the magic `PFEMREDU`, the format version (`u32`), the key (`u64`), the
//! body's values (counts as `u64`, numbers as the bits of `f64`, all little-endian) and a checksum
//! (`u64`) of every byte before it.
//!
//! **Reading streams the file.** The small fields come through a buffer; each vector is read
//! straight into its own memory, 64 KiB at a time, and the checksum takes each piece while it is
//! still in the processor's cache. Most of a body is its modes' stresses: reading the whole file
//! into memory first and converting it afterwards would touch every byte twice and make the system
//! supply twice the fresh memory (page faults, most of the cost of a read).
//!
//! **The checksum** is FNV-1a's step (xor, then multiply by the FNV prime) over the little-endian
//! 8-byte words in four interleaved lanes (word `i` goes to lane `i mod 4`), so that four
//! independent multiplications are in flight instead of one chain; the bytes after the last whole
//! word go to lane 0 one at a time, and the lanes are folded into one word by the same step.

use std::io::Read;

use super::super::{ArcPoint, ProxyModes, ReducedBody, StressModes};
use super::CACHE_VERSION;
use crate::error::Error;
use crate::store::bytes::Writer;

const MAGIC: &[u8; 8] = b"PFEMREDU";

/// Bytes read (and checksummed) at a time into a vector.
const PIECE: usize = 1 << 16;

const FNV_OFFSET: u64 = crate::store::Fnv::OFFSET;
const FNV_PRIME: u64 = crate::store::Fnv::PRIME;

fn step(h: u64, word: u64) -> u64 {
    (h ^ word).wrapping_mul(FNV_PRIME)
}

/// The checksum of the module doc, taken piece by piece.
pub(super) struct Checksum {
    lanes: [u64; 4],
    /// Bytes of an unfinished 32-byte block.
    pending: [u8; 32],
    fill: usize,
}

impl Checksum {
    pub(super) fn new() -> Self {
        Self {
            lanes: std::array::from_fn(|i| FNV_OFFSET.wrapping_add(i as u64)),
            pending: [0; 32],
            fill: 0,
        }
    }

    fn block(&mut self, block: &[u8]) {
        for (lane, w) in self.lanes.iter_mut().zip(block.chunks_exact(8)) {
            *lane = step(*lane, u64::from_le_bytes(w.try_into().expect("8 bytes")));
        }
    }

    /// Takes the next `bytes`.
    pub(super) fn update(&mut self, mut bytes: &[u8]) {
        if self.fill > 0 {
            let k = (32 - self.fill).min(bytes.len());
            self.pending[self.fill..self.fill + k].copy_from_slice(&bytes[..k]);
            self.fill += k;
            bytes = &bytes[k..];
            if self.fill < 32 {
                return;
            }
            let block = self.pending;
            self.block(&block);
            self.fill = 0;
        }
        let mut blocks = bytes.chunks_exact(32);
        for b in &mut blocks {
            self.block(b);
        }
        let rest = blocks.remainder();
        self.pending[..rest.len()].copy_from_slice(rest);
        self.fill = rest.len();
    }

    /// The checksum of every byte taken.
    pub(super) fn finish(mut self) -> u64 {
        let pending = self.pending;
        let mut words = pending[..self.fill].chunks_exact(8);
        for (lane, w) in self.lanes.iter_mut().zip(&mut words) {
            *lane = step(*lane, u64::from_le_bytes(w.try_into().expect("8 bytes")));
        }
        for &b in words.remainder() {
            self.lanes[0] = step(self.lanes[0], u64::from(b));
        }
        self.lanes.iter().fold(FNV_OFFSET, |h, &l| step(h, l))
    }
}

fn bad(why: impl std::fmt::Display) -> Error {
    Error::Input(format!("reduced body cache: {why}"))
}

/// Reads the fields of a file of `left` bytes before its checksum from `src`, taking each into
/// the checksum.
struct Fields<R> {
    src: R,
    sum: Checksum,
    left: u64,
}

impl<R: Read> Fields<R> {
    fn fill(&mut self, dst: &mut [u8], what: &str) -> Result<(), Error> {
        if dst.len() as u64 > self.left {
            return Err(bad(format!("truncated at {what}")));
        }
        self.src.read_exact(dst).map_err(|e| bad(format!("{what}: {e}")))?;
        self.sum.update(dst);
        self.left -= dst.len() as u64;
        Ok(())
    }

    fn u64(&mut self, what: &str) -> Result<u64, Error> {
        let mut b = [0; 8];
        self.fill(&mut b, what)?;
        Ok(u64::from_le_bytes(b))
    }

    fn f64(&mut self, what: &str) -> Result<f64, Error> {
        self.u64(what).map(f64::from_bits)
    }

    /// A count of items of at least `size` bytes each, checked against the bytes left.
    fn count(&mut self, what: &str, size: u64) -> Result<usize, Error> {
        let n = self.u64(what)?;
        if n > self.left / size {
            return Err(bad(format!("{what}: {n} items in {} bytes", self.left)));
        }
        usize::try_from(n).map_err(|_| bad(format!("{what}: {n} items")))
    }

    /// `n` little-endian 8-byte words straight into their memory.
    fn words<T: bytemuck::Pod + Default>(&mut self, n: usize, what: &str) -> Result<Vec<T>, Error> {
        let mut v = vec![T::default(); n];
        for piece in bytemuck::cast_slice_mut::<T, u8>(&mut v).chunks_mut(PIECE) {
            self.fill(piece, what)?;
        }
        if cfg!(target_endian = "big") {
            for w in bytemuck::cast_slice_mut::<T, u64>(&mut v) {
                *w = u64::from_le(*w);
            }
        }
        Ok(v)
    }

    fn vec(&mut self, what: &str) -> Result<Vec<f64>, Error> {
        let n = self.count(what, 8)?;
        self.words(n, what)
    }

    fn vecs(&mut self, what: &str) -> Result<Vec<Vec<f64>>, Error> {
        let n = self.count(what, 8)?;
        (0..n).map(|_| self.vec(what)).collect()
    }
}

fn write_vecs(w: &mut Writer, vs: &[Vec<f64>]) {
    w.usize(vs.len());
    vs.iter().for_each(|v| w.vec(v));
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
    let mut sum = Checksum::new();
    sum.update(&w.0);
    w.u64(sum.finish());
    w.0
}

/// Reads [`to_bytes`]'s bytes of the body with `key`; anything else is an error.
pub fn from_bytes(bytes: &[u8], key: u64) -> Result<ReducedBody, Error> {
    read(bytes, bytes.len() as u64, key)
}

/// Reads the cache file at `path` of the body with `key` (see [`from_bytes`]).
pub fn from_file(path: &std::path::Path, key: u64) -> Result<ReducedBody, Error> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let len = file.metadata().map_err(|e| Error::io(path, e))?.len();
    read(std::io::BufReader::new(file), len, key)
}

/// Reads the `len` bytes of a cache file from `src`.
fn read(src: impl Read, len: u64, key: u64) -> Result<ReducedBody, Error> {
    if len < 8 + 4 + 8 + 8 {
        return Err(bad("not a cache file"));
    }
    let mut r = Fields {
        src,
        sum: Checksum::new(),
        left: len - 8,
    };
    let mut head = [0; 12];
    r.fill(&mut head, "header")?;
    if &head[..8] != MAGIC {
        return Err(bad("not a cache file"));
    }
    let version = u32::from_le_bytes(head[8..].try_into().expect("4 bytes"));
    if version != CACHE_VERSION || r.u64("key")? != key {
        return Err(bad("another version or body"));
    }
    let shapes = r.vecs("shapes")?;
    let [stiffness, b, d, hub, g] = [(); 5].map(|_| r.vec("operators"));
    let (stiffness, b, d, hub, g) = (stiffness?, b?, d?, hub?, g?);
    let inertia = r.f64("inertia")?;
    let s0 = [r.f64("s0")?, r.f64("s0")?];
    let s: [Vec<f64>; 2] = r.vecs("s")?.try_into().map_err(|_| bad("s"))?;
    let mass = r.f64("mass")?;
    let count = r.count("arc", 8)?;
    let mut arc = Vec::with_capacity(count);
    for _ in 0..count {
        let reference = [r.f64("arc")?, r.f64("arc")?];
        let modes: [Vec<f64>; 2] = r.vecs("arc")?.try_into().map_err(|_| bad("arc modes"))?;
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
    let n = r.count("stress nodes", 8)?;
    let nodes = r
        .words::<u64>(n, "stress nodes")?
        .into_iter()
        .map(|k| usize::try_from(k).map_err(|_| bad("stress nodes")))
        .collect::<Result<Vec<_>, _>>()?;
    let counts = r.vec("stress counts")?;
    if r.left != 0 {
        return Err(bad("trailing bytes"));
    }
    let mut stored = [0; 8];
    r.src
        .read_exact(&mut stored)
        .map_err(|e| bad(format!("checksum: {e}")))?;
    if r.sum.finish() != u64::from_le_bytes(stored) {
        return Err(bad("damaged (checksum)"));
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

    #[test]
    fn the_checksum_taken_in_pieces_is_the_checksum_of_the_whole() {
        let bytes: Vec<u8> = (0..1000u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect();
        let mut whole = Checksum::new();
        whole.update(&bytes);
        let whole = whole.finish();
        for cut in [1, 7, 31, 32, 33, 100, 999] {
            let mut parts = Checksum::new();
            for piece in bytes.chunks(cut) {
                parts.update(piece);
            }
            assert_eq!(parts.finish(), whole, "pieces of {cut} bytes");
        }
        // every byte counts, also in the tail and across lanes
        for at in [0, 8, 16, 24, 500, 999] {
            let mut changed = bytes.clone();
            changed[at] ^= 1;
            let mut c = Checksum::new();
            c.update(&changed);
            assert_ne!(c.finish(), whole, "byte {at} flipped");
        }
        let mut swapped = bytes.clone();
        assert_ne!(bytes[..8], bytes[8..16]);
        swapped[..16].rotate_left(8);
        let mut c = Checksum::new();
        c.update(&swapped);
        assert_ne!(c.finish(), whole, "two words exchanged between lanes");
    }
}
