//! The hinge: the mean displacement of the "rotation" edge vanishes,
//!
//! ```text
//! c(u) = (1/|Γ|) ∫_Γ u ds = Σ_a w_a u_a = 0        (two rows, x and y),
//! ```
//!
//! with `w_a = (1/|Γ|) ∫_Γ N_a ds` (so `Σ w_a = 1`), the tutorial's `NumberSpace` constraint up to
//! the constant factor `|Γ|`. The body may rotate freely about the pivot (the edge's centroid, the
//! origin). The two Lagrange multipliers `λ` are forces: stationarity reads `∇Φ + Cᵀλ = 0`, so the
//! force the hinge exerts on the body is `−λ` \[N\] ([`Hinge::reaction`]).

use crate::error::Error;
use crate::fe::for_each_edge_point;
use crate::mesh::Mesh;

/// Mean-displacement hinge on a named boundary.
#[derive(Clone, Debug)]
pub struct Hinge {
    /// Nodes on the hinge edge.
    pub nodes: Vec<usize>,
    /// Their weights `w_a` (sum 1).
    pub weights: Vec<f64>,
    /// Length of the hinge edge \[m\].
    pub length: f64,
}

impl Hinge {
    /// The hinge on boundary `name` of `mesh` (the tutorial's "rotation").
    pub fn new(mesh: &Mesh, name: &str) -> Result<Self, Error> {
        let mut acc = std::collections::BTreeMap::<usize, f64>::new();
        let mut length = 0.0;
        for_each_edge_point(mesh, name, |nodes, n, _x, ds| {
            length += ds;
            for a in 0..3 {
                *acc.entry(nodes[a]).or_default() += n[a] * ds;
            }
        });
        if acc.is_empty() || length <= 0.0 {
            return Err(Error::Mesh(format!(
                "the mesh has no boundary named \"{name}\" for the hinge"
            )));
        }
        let (nodes, weights) = acc.into_iter().map(|(n, w)| (n, w / length)).unzip();
        Ok(Self { nodes, weights, length })
    }

    /// `c(u)` \[m\].
    pub fn value(&self, u: &[f64]) -> [f64; 2] {
        let mut c = [0.0; 2];
        for (&n, &w) in self.nodes.iter().zip(&self.weights) {
            c[0] += w * u[2 * n];
            c[1] += w * u[2 * n + 1];
        }
        c
    }

    /// The two rows of `C` as dense vectors of length `ndof`.
    pub fn dense_rows(&self, ndof: usize) -> [Vec<f64>; 2] {
        let mut rows = [vec![0.0; ndof], vec![0.0; ndof]];
        for (&n, &w) in self.nodes.iter().zip(&self.weights) {
            rows[0][2 * n] = w;
            rows[1][2 * n + 1] = w;
        }
        rows
    }

    /// The force of the hinge on the body for multipliers `λ` \[N\].
    pub fn reaction(lambda: [f64; 2]) -> [f64; 2] {
        [-lambda[0], -lambda[1]]
    }
}
