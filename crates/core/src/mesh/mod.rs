//! The finite-element mesh: curved six-node triangles with named boundaries.
//!
//! Node numbering: the triangle vertices come first (`0..num_vertices`), then one node per edge
//! (`num_vertices..nodes.len()`). Every element is a [`crate::element::Tri6`] with its nodes in the
//! order drawn there (vertices 0, 1, 2 counter-clockwise, then the mid-edge nodes of the edges
//! 0→1, 1→2, 2→0). With `order = 2` the mid-edge node of an edge that lies on a circle of the
//! geometry sits exactly on that circle (the isoparametric map curves the element); with
//! `order = 1` every mid-edge node is the midpoint of its straight edge.
//!
//! Boundary edges carry the index of their name in [`Mesh::boundary_names`] ("rotation" for the
//! hinge edge, "contact_head" for the outer head circle, "default" for the rest). The whole domain
//! is one region, [`Mesh::region_name`] ("pendulum").
//!
//! Submodules: [`mod@generate`] (the pipeline and its guarantees), [`size`] (the graded size field),
//! `refine` (Delaunay refinement with curved boundary splits), `measure` (area, moments,
//! Jacobians and angles as methods of [`Mesh`]), [`mod@bench`] (timings).

pub mod bench;
pub mod block;
pub mod cache;
pub mod generate;
pub mod gmsh_read;
mod measure;
mod refine;
pub mod size;

pub use generate::{forget_last, generate, generate_with_stats, max_size_warning, mesh_shape, MeshStats};

/// One edge of the boundary, oriented with the domain on its left.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BoundaryEdge {
    /// `[start vertex, end vertex, mid-edge node]`.
    pub nodes: [usize; 3],
    /// Index into [`Mesh::boundary_names`].
    pub name: usize,
    /// The triangle this edge belongs to.
    pub triangle: usize,
    /// Local edge number in that triangle (0: nodes 0→1, 1: 1→2, 2: 2→0).
    pub local_edge: usize,
}

/// A conforming mesh of six-node triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// Node coordinates \[m\], vertices first.
    pub nodes: Vec<[f64; 2]>,
    /// Number of triangle vertices (corner nodes).
    pub num_vertices: usize,
    /// Triangles, counter-clockwise, Tri6 node order.
    pub triangles: Vec<[usize; 6]>,
    /// Boundary edges.
    pub boundary_edges: Vec<BoundaryEdge>,
    /// Boundary names, indexed by [`BoundaryEdge::name`].
    pub boundary_names: Vec<String>,
    /// Name of the (single) region.
    pub region_name: String,
    /// Geometric order, 1 or 2.
    pub order: u32,
}

impl Mesh {
    /// Number of nodes (vertices and mid-edge nodes).
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Index of a boundary name, if the mesh has it.
    pub fn boundary_id(&self, name: &str) -> Option<usize> {
        self.boundary_names.iter().position(|n| n == name)
    }

    /// The boundary edges with the given name.
    pub fn edges_named<'a>(&'a self, name: &str) -> impl Iterator<Item = &'a BoundaryEdge> + 'a {
        let id = self.boundary_id(name);
        self.boundary_edges.iter().filter(move |e| Some(e.name) == id)
    }

    /// Sorted, de-duplicated nodes (vertices and mid-edge nodes) on the named boundary.
    pub fn nodes_on(&self, name: &str) -> Vec<usize> {
        let mut v: Vec<usize> = self.edges_named(name).flat_map(|e| e.nodes).collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}
