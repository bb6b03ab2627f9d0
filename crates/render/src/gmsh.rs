//! Gmsh 4.1 ASCII mesh files (`.msh`) with physical names.
//!
//! Layout: one curve entity per boundary name (tags 1, 2, … in the order of
//! [`Mesh::boundary_names`]) and one surface entity (tag 1). Physical groups: the boundary names
//! as 1-D groups (tags 1, 2, …), the region name as the 2-D group (tag = number of boundary
//! names + 1). All nodes are written in one block classified on the surface (tags 1-based, in mesh
//! order); elements are 3-node lines (type 8: ends, then mid node) per boundary name, then 6-node
//! triangles (type 9: corners, then the mid nodes of edges 0→1, 1→2, 2→0 — the mesh's own order).

use std::io::Write;
use std::path::Path;

use crate::{Error, Mesh};
use pendulum_fem_core::store::write_atomically;

/// Gmsh element type of the 3-node line.
pub const GMSH_LINE3: u32 = 8;
/// Gmsh element type of the 6-node triangle.
pub const GMSH_TRIANGLE6: u32 = 9;

/// Writes `mesh` to `path` in Gmsh 4.1 ASCII format.
pub fn write_msh(path: &Path, mesh: &Mesh) -> Result<(), Error> {
    write_atomically(path, |w| write_msh_to(w, mesh))
}

/// Writes `mesh` in Gmsh 4.1 ASCII format to any writer.
pub fn write_msh_to(w: &mut dyn Write, mesh: &Mesh) -> std::io::Result<()> {
    let names = &mesh.boundary_names;
    let nb = names.len();
    let (lo, hi) = bounding_box(mesh);
    writeln!(w, "$MeshFormat\n4.1 0 8\n$EndMeshFormat")?;
    writeln!(w, "$PhysicalNames\n{}", nb + 1)?;
    for (i, n) in names.iter().enumerate() {
        writeln!(w, "1 {} \"{}\"", i + 1, n)?;
    }
    writeln!(w, "2 {} \"{}\"", nb + 1, mesh.region_name)?;
    writeln!(w, "$EndPhysicalNames")?;

    writeln!(w, "$Entities\n0 {nb} 1 0")?;
    for i in 0..nb {
        let (clo, chi) = edge_box(mesh, i).unwrap_or((lo, hi));
        writeln!(
            w,
            "{} {:e} {:e} 0 {:e} {:e} 0 1 {} 0",
            i + 1,
            clo[0],
            clo[1],
            chi[0],
            chi[1],
            i + 1
        )?;
    }
    let curves: Vec<String> = (1..=nb).map(|i| i.to_string()).collect();
    writeln!(
        w,
        "1 {:e} {:e} 0 {:e} {:e} 0 1 {} {} {}",
        lo[0],
        lo[1],
        hi[0],
        hi[1],
        nb + 1,
        nb,
        curves.join(" ")
    )?;
    writeln!(w, "$EndEntities")?;

    let nn = mesh.nodes.len();
    writeln!(w, "$Nodes\n1 {nn} 1 {nn}\n2 1 0 {nn}")?;
    for i in 1..=nn {
        writeln!(w, "{i}")?;
    }
    for p in &mesh.nodes {
        writeln!(w, "{:.17e} {:.17e} 0", p[0], p[1])?;
    }
    writeln!(w, "$EndNodes")?;

    let blocks: Vec<(usize, Vec<&crate::mesh::BoundaryEdge>)> = (0..nb)
        .map(|i| {
            (
                i,
                mesh.boundary_edges.iter().filter(|e| e.name == i).collect::<Vec<_>>(),
            )
        })
        .filter(|(_, v)| !v.is_empty())
        .collect();
    let ne = mesh.boundary_edges.len() + mesh.triangles.len();
    writeln!(w, "$Elements\n{} {ne} 1 {ne}", blocks.len() + 1)?;
    let mut tag = 1;
    for (i, edges) in &blocks {
        writeln!(w, "1 {} {GMSH_LINE3} {}", i + 1, edges.len())?;
        for e in edges {
            writeln!(w, "{tag} {} {} {}", e.nodes[0] + 1, e.nodes[1] + 1, e.nodes[2] + 1)?;
            tag += 1;
        }
    }
    writeln!(w, "2 1 {GMSH_TRIANGLE6} {}", mesh.triangles.len())?;
    for t in &mesh.triangles {
        write!(w, "{tag}")?;
        for n in t {
            write!(w, " {}", n + 1)?;
        }
        writeln!(w)?;
        tag += 1;
    }
    writeln!(w, "$EndElements")?;
    Ok(())
}

fn bounding_box(mesh: &Mesh) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in &mesh.nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

fn edge_box(mesh: &Mesh, name: usize) -> Option<([f64; 2], [f64; 2])> {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    let mut any = false;
    for e in mesh.boundary_edges.iter().filter(|e| e.name == name) {
        for &n in &e.nodes {
            any = true;
            for k in 0..2 {
                lo[k] = lo[k].min(mesh.nodes[n][k]);
                hi[k] = hi[k].max(mesh.nodes[n][k]);
            }
        }
    }
    any.then_some((lo, hi))
}
