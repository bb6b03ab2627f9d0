//! # pendulum-fem-render
//!
//! The files and pictures of a run: VTU/PVD/VTM for ParaView, Gmsh `.msh`, the θ and energy
//! plots, the animations, the HTML viewer, and a sweep's summary figures. They watch a run as a
//! [`RunObserver`](pendulum_fem_run::RunObserver) ([`pictures::attach`]). The numerics are
//! `pendulum-fem-core`, the run driver `pendulum-fem-run`, the command line `pendulum-fem`; the
//! FMU and the Python module do without this crate (and its image and font code).
#![warn(missing_docs)]

// The core's modules under the names the writers have always used (`crate::Mesh`, `crate::config`).
pub use pendulum_fem_core::simulation::Frame;
pub(crate) use pendulum_fem_core::{config, mesh, simulation, Config, Error, Mesh};

pub mod anim;
mod font;
pub mod gmsh;
pub mod modes;
pub mod pictures;
pub mod plot;
pub mod pvd;
mod raster;
pub mod summary_plot;
pub mod viewer;
pub mod vtm;
pub mod vtu;
pub mod wall;
pub mod writers;

pub use writers::FrameWriters;

/// Values of one field at every mesh node (vertices and mid-edge nodes).
#[derive(Clone, Copy, Debug)]
pub enum FieldData<'a> {
    /// One value per node.
    Scalar(&'a [f64]),
    /// `[x, y]` per node.
    Vector(&'a [[f64; 2]]),
    /// Symmetric 2-D tensor `[xx, yy, xy]` per node.
    Tensor(&'a [[f64; 3]]),
    /// One value per node, stored as Float32 (about seven significant digits).
    Scalar32(&'a [f64]),
    /// Symmetric 2-D tensor `[xx, yy, xy]` per node, stored as Float32.
    Tensor32(&'a [[f64; 3]]),
    /// A small non-negative integer per entry (a flag or an index), stored as UInt8.
    Label(&'a [u8]),
}

impl FieldData<'_> {
    /// Number of entries (nodes or cells).
    pub fn len(&self) -> usize {
        match self {
            Self::Scalar(v) | Self::Scalar32(v) => v.len(),
            Self::Vector(v) => v.len(),
            Self::Tensor(v) | Self::Tensor32(v) => v.len(),
            Self::Label(v) => v.len(),
        }
    }

    /// Whether there are no entries.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A named nodal field.
#[derive(Clone, Copy, Debug)]
pub struct Field<'a> {
    /// Name shown in ParaView.
    pub name: &'a str,
    /// Values.
    pub data: FieldData<'a>,
}

/// Standard base64 (RFC 4648, with padding).
pub(crate) fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        out.push(A[(n >> 18) as usize & 63] as char);
        out.push(A[(n >> 12) as usize & 63] as char);
        out.push(if c.len() > 1 {
            A[(n >> 6) as usize & 63] as char
        } else {
            '='
        });
        out.push(if c.len() > 2 { A[n as usize & 63] as char } else { '=' });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::base64;

    #[test]
    fn base64_matches_rfc4648_vectors() {
        for (i, o) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(i.as_bytes()), o);
        }
    }
}
