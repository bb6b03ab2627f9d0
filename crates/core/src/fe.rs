//! Reference-configuration data of every element, computed once (total Lagrangian).
//!
//! For each element `e` and quadrature point `q` of the degree-4 rule the cache holds the gradients
//! of the six basis functions with respect to the reference coordinates, `∇₀N_a = J₀⁻ᵀ ∇_ξ N_a`
//! (`J₀ = ∂X/∂ξ`, the isoparametric map through all six nodes, so curved edges are exact), and the
//! weight `w_q · det J₀ · thickness` \[m³\]. Unknowns are interleaved, `u = [u₀ₓ, u₀ᵧ, u₁ₓ, …]`, so node
//! `a` owns the degrees of freedom `2a` and `2a + 1`.
//!
//! A reference element with `det J₀ ≤ 0` at a quadrature point is an error at set-up that names the
//! element ([`Error::InvertedElement`]), never a NaN later.

use crate::element::{jacobian, Tri6};
use crate::error::Error;
use crate::mesh::Mesh;
use crate::quadrature::TriangleRule;

/// Per-element, per-quadrature-point reference data.
#[derive(Clone, Debug)]
pub struct FeCache {
    /// Quadrature points per element.
    pub points_per_element: usize,
    /// `∇₀N_a` for every (element, point), element-major.
    pub grads: Vec<[[f64; 2]; 6]>,
    /// `w · det J₀ · thickness` for every (element, point) \[m³\].
    pub weights: Vec<f64>,
}

/// The six node coordinates of element `e`.
pub fn element_coordinates(mesh: &Mesh, e: usize) -> [[f64; 2]; 6] {
    mesh.triangles[e].map(|n| mesh.nodes[n])
}

impl FeCache {
    /// Builds the cache for `mesh` with `rule`, scaling the weights by `thickness`.
    pub fn new(mesh: &Mesh, rule: &TriangleRule, thickness: f64) -> Result<Self, Error> {
        let nq = rule.points.len();
        let mut grads = Vec::with_capacity(mesh.triangles.len() * nq);
        let mut weights = Vec::with_capacity(mesh.triangles.len() * nq);
        for e in 0..mesh.triangles.len() {
            let x = element_coordinates(mesh, e);
            for (q, (xi, w)) in rule.iter().enumerate() {
                let (j, g) = jacobian(&x, xi);
                let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
                if det.is_nan() || det <= 0.0 {
                    return Err(Error::InvertedElement {
                        element: e,
                        quad_point: q,
                        det_j: det,
                    });
                }
                // J⁻ᵀ ∇ξ N: ∇X N = J⁻ᵀ g, J⁻¹ = [[j11, −j01], [−j10, j00]] / det
                let inv = [[j[1][1] / det, -j[0][1] / det], [-j[1][0] / det, j[0][0] / det]];
                let grad = g.map(|ga| {
                    [
                        inv[0][0] * ga[0] + inv[1][0] * ga[1],
                        inv[0][1] * ga[0] + inv[1][1] * ga[1],
                    ]
                });
                grads.push(grad);
                weights.push(w * det * thickness);
            }
        }
        Ok(Self {
            points_per_element: nq,
            grads,
            weights,
        })
    }
}

/// Integrates `f(X) · N_a(X)` for every element node with `rule`, calling `visit(e, a_local, X, w·detJ)`
/// at each quadrature point and node; used for mass, loads and rigid-body moments.
pub fn for_each_point(mesh: &Mesh, rule: &TriangleRule, mut visit: impl FnMut(usize, &[f64; 6], [f64; 2], f64)) {
    let basis: Vec<[f64; 6]> = rule.points.iter().map(|&xi| Tri6::basis(xi)).collect();
    for e in 0..mesh.triangles.len() {
        let x = element_coordinates(mesh, e);
        for (q, (xi, w)) in rule.iter().enumerate() {
            let (j, _) = jacobian(&x, xi);
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            let n = &basis[q];
            let mut p = [0.0; 2];
            for a in 0..6 {
                p[0] += n[a] * x[a][0];
                p[1] += n[a] * x[a][1];
            }
            visit(e, n, p, w * det);
        }
    }
}

/// Visits the 3-point Gauss points of every edge of the boundary `name`: `visit(nodes, N, x, ds)`
/// with the edge's `[start, end, mid]` nodes, the quadratic edge basis `N` at the point, the point
/// `x` and the weighted arc length `ds` (the map through all three nodes, exact on curved edges).
pub fn for_each_edge_point(mesh: &Mesh, name: &str, mut visit: impl FnMut([usize; 3], [f64; 3], [f64; 2], f64)) {
    for e in mesh.edges_named(name) {
        let x = e.nodes.map(|n| mesh.nodes[n]);
        for (s, w) in crate::quadrature::GAUSS3_UNIT {
            let n = Tri6::edge_basis(s);
            let dn = Tri6::edge_basis_derivatives(s);
            let dx = [0, 1].map(|i| (0..3).map(|a| dn[a] * x[a][i]).sum::<f64>());
            let p = [0, 1].map(|i| (0..3).map(|a| n[a] * x[a][i]).sum::<f64>());
            visit(e.nodes, n, p, w * dx[0].hypot(dx[1]));
        }
    }
}
