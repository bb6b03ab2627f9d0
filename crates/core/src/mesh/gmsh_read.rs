//! Reading Gmsh 4.1 meshes (`.msh`, ASCII or binary) into a [`Mesh`]: any planar shape can swing.
//!
//! **What is read.** `$MeshFormat` (version 4.1, file type 0 = ASCII or 1 = binary with 8-byte
//! `size_t`, either byte order), `$PhysicalNames`, `$Entities` (which physical groups each curve and
//! surface belongs to), `$Nodes` and `$Elements`; other sections are skipped. Triangles are 3-node
//! (type 2) or 6-node (type 9: corners, then the mid nodes of the edges 0→1, 1→2, 2→0), all of one
//! kind; 2- and 3-node lines (types 1 and 8) name boundary edges through the physical groups of
//! their curves; points (type 15) are ignored. The nodes must lie in the plane `z = 0`.
//!
//! **The mesh built.** Corner nodes first, then mid-edge nodes, each in the order of their tags
//! (so a file written by `pendulum_fem_render::gmsh::write_msh` reads back with the same numbering); 3-node
//! triangles get straight mid-edge nodes (`order = 1`), 6-node triangles keep theirs (`order = 2`).
//! Clockwise triangles are turned counter-clockwise. Every edge used by one triangle is a boundary
//! edge, named by the physical group of the line element on it (`"default"` without one); the
//! physical group `rotation` (the hinge) is required, `contact_head` is optional, others are kept
//! by name. The region is named by the triangles' 2-D physical group (`"pendulum"` without one).
//!
//! **Errors** name the file and the line (ASCII) or byte offset (binary) and what was expected:
//! a missing section, a count that does not fit the file, an unknown node, an unsupported element
//! type, a degenerate or non-conforming triangle, a named line that is not on the boundary.

mod build;
mod parser;

use std::collections::HashMap;
use std::path::Path;

use crate::error::Error;
use crate::mesh::Mesh;
use build::build_mesh;
use parser::Parser;

/// The boundary name the hinge must carry.
pub const HINGE_NAME: &str = "rotation";

/// Reads a Gmsh 4.1 file.
pub fn read_msh(path: &Path) -> Result<Mesh, Error> {
    let data = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_msh(&data, &path.display().to_string())
}

/// Parses the bytes of a Gmsh 4.1 file; `source` names it in error messages.
pub fn parse_msh(data: &[u8], source: &str) -> Result<Mesh, Error> {
    let raw = Parser::new(data, source).parse()?;
    build_mesh(raw, source)
}

/// What the file holds, before it becomes a mesh.
#[derive(Default)]
struct RawMesh {
    /// `(dim, tag) → name`.
    physical_names: HashMap<(i32, i32), String>,
    /// Physical tags of curves (dim 1) and surfaces (dim 2): `(dim, entity tag) → tags`.
    entity_physicals: HashMap<(i32, i32), Vec<i32>>,
    /// Node tag → `[x, y, z]`.
    nodes: HashMap<u64, [f64; 3]>,
    /// `(element tag, entity tag, node tags)` of triangles.
    triangles: Vec<(u64, i32, Vec<u64>)>,
    /// `(element tag, entity tag, node tags)` of lines.
    lines: Vec<(u64, i32, Vec<u64>)>,
}
