//! The quadrature points of the head's arc: Gauss points on every curved edge of the named
//! boundary with their edge basis, reference position and weight, and the rigid wall's
//! constructor that lays them out.

use super::WallContact;
use crate::element::Tri6;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::quadrature::gauss_legendre_unit;

/// One quadrature point of the contact arc.
#[derive(Clone, Debug)]
pub(super) struct ContactPoint {
    /// The edge's `[start, end, mid]` nodes.
    pub(super) nodes: [usize; 3],
    /// The edge's index among the arc's edges.
    pub(super) edge: usize,
    /// The quadratic edge basis at the point.
    pub(super) basis: [f64; 3],
    /// Reference `x` of the point \[m\].
    pub(super) x_ref: f64,
    /// Reference `y` of the point \[m\].
    pub(super) y_ref: f64,
    /// Reference arc length times thickness \[m²\].
    pub(super) weight: f64,
}

impl WallContact {
    /// The arc's quadrature points: the edge's `[start, end, mid]` nodes, the edge basis at the
    /// point and its weight (reference arc length times thickness \[m²\]).
    pub fn arc_points(&self) -> impl Iterator<Item = ([usize; 3], [f64; 3], f64)> + '_ {
        self.points.iter().map(|p| (p.nodes, p.basis, p.weight))
    }

    /// The wall at `face_x` with stiffness `stiffness` against the boundary `name` of `mesh`, with
    /// `points_per_edge` Gauss points on every edge (exact arc geometry through the edge's three
    /// nodes) and the body's `thickness`.
    pub fn new(
        mesh: &Mesh,
        name: &str,
        face_x: f64,
        stiffness: f64,
        thickness: f64,
        points_per_edge: usize,
    ) -> Result<Self, Error> {
        let rule = gauss_legendre_unit(points_per_edge.max(1));
        let mut points = Vec::new();
        for (edge, e) in mesh.edges_named(name).enumerate() {
            let x = e.nodes.map(|n| mesh.nodes[n]);
            for &(s, w) in &rule {
                let n = Tri6::edge_basis(s);
                let dn = Tri6::edge_basis_derivatives(s);
                let dx = [0, 1].map(|i| (0..3).map(|a| dn[a] * x[a][i]).sum::<f64>());
                points.push(ContactPoint {
                    nodes: e.nodes,
                    edge,
                    basis: n,
                    x_ref: (0..3).map(|a| n[a] * x[a][0]).sum(),
                    y_ref: (0..3).map(|a| n[a] * x[a][1]).sum(),
                    weight: w * dx[0].hypot(dx[1]) * thickness,
                });
            }
        }
        if points.is_empty() {
            return Err(Error::Mesh(format!(
                "the mesh has no boundary named \"{name}\" for the contact with the wall"
            )));
        }
        Ok(Self {
            face_x,
            stiffness,
            end_point: false,
            points,
            face: None,
            reference: mesh.nodes.clone(),
        })
    }
}
