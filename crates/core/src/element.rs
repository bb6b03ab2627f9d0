//! The six-node quadratic triangle (P2) on the reference triangle `(0,0), (1,0), (0,1)`.
//!
//! ```text
//!  η
//!  2
//!  | \
//!  5   4
//!  |     \
//!  0---3---1  ξ
//! ```
//!
//! Node 3 lies on edge 0→1, node 4 on edge 1→2, node 5 on edge 2→0. With barycentric coordinates
//! `L0 = 1 − ξ − η`, `L1 = ξ`, `L2 = η` the basis is `N_v = L_v (2 L_v − 1)` at the corners and
//! `N_3 = 4 L0 L1`, `N_4 = 4 L1 L2`, `N_5 = 4 L2 L0` at the mid-edge nodes. The same functions map
//! the reference triangle onto a (possibly curved) mesh element: the isoparametric map.

/// Quadratic six-node triangle.
pub struct Tri6;

impl Tri6 {
    /// Number of nodes.
    pub const NUM_NODES: usize = 6;
    /// Reference coordinates of the nodes.
    pub const NODES: [[f64; 2]; 6] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]];
    /// The local node pairs of the three edges and the mid-edge node: `[start, end, mid]`.
    pub const EDGES: [[usize; 3]; 3] = [[0, 1, 3], [1, 2, 4], [2, 0, 5]];

    /// Basis function values at `ξ = [ξ, η]`.
    pub fn basis(xi: [f64; 2]) -> [f64; 6] {
        let (l1, l2) = (xi[0], xi[1]);
        let l0 = 1.0 - l1 - l2;
        [
            l0 * (2.0 * l0 - 1.0),
            l1 * (2.0 * l1 - 1.0),
            l2 * (2.0 * l2 - 1.0),
            4.0 * l0 * l1,
            4.0 * l1 * l2,
            4.0 * l2 * l0,
        ]
    }

    /// Basis gradients with respect to `(ξ, η)`: entry `a` is `[∂N_a/∂ξ, ∂N_a/∂η]`.
    pub fn basis_gradients(xi: [f64; 2]) -> [[f64; 2]; 6] {
        let (l1, l2) = (xi[0], xi[1]);
        let l0 = 1.0 - l1 - l2;
        // dL0 = (−1, −1), dL1 = (1, 0), dL2 = (0, 1).
        let c0 = 4.0 * l0 - 1.0;
        [
            [-c0, -c0],
            [4.0 * l1 - 1.0, 0.0],
            [0.0, 4.0 * l2 - 1.0],
            [4.0 * (l0 - l1), -4.0 * l1],
            [4.0 * l2, 4.0 * l1],
            [-4.0 * l2, 4.0 * (l0 - l2)],
        ]
    }

    /// Quadratic edge basis on `s ∈ [0, 1]` for `[start, end, mid]`: `(1−s)(1−2s)`, `s(2s−1)`, `4s(1−s)`.
    pub fn edge_basis(s: f64) -> [f64; 3] {
        [(1.0 - s) * (1.0 - 2.0 * s), s * (2.0 * s - 1.0), 4.0 * s * (1.0 - s)]
    }

    /// Derivatives of [`Tri6::edge_basis`] with respect to `s`.
    pub fn edge_basis_derivatives(s: f64) -> [f64; 3] {
        [4.0 * s - 3.0, 4.0 * s - 1.0, 4.0 - 8.0 * s]
    }
}

/// The isoparametric Jacobian `J₀ = ∂X/∂ξ` of an element at `ξ` and the basis gradients in ξ.
pub fn jacobian(x: &[[f64; 2]; 6], xi: [f64; 2]) -> ([[f64; 2]; 2], [[f64; 2]; 6]) {
    let g = Tri6::basis_gradients(xi);
    let mut j = [[0.0; 2]; 2];
    for a in 0..6 {
        for i in 0..2 {
            for d in 0..2 {
                j[i][d] += x[a][i] * g[a][d];
            }
        }
    }
    (j, g)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLES: [[f64; 2]; 5] = [[0.2, 0.3], [0.1, 0.05], [0.6, 0.2], [1.0 / 3.0, 1.0 / 3.0], [0.0, 0.9]];

    #[test]
    fn tri6_is_nodal() {
        for (a, xi) in Tri6::NODES.iter().enumerate() {
            let n = Tri6::basis(*xi);
            for (b, nb) in n.iter().enumerate() {
                let expected = if a == b { 1.0 } else { 0.0 };
                assert!((nb - expected).abs() < 1e-15, "N_{b} at node {a} = {nb}");
            }
        }
    }

    #[test]
    fn tri6_partition_of_unity_and_gradients_match_finite_differences() {
        let h = 1e-6;
        for xi in SAMPLES {
            let n = Tri6::basis(xi);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            let g = Tri6::basis_gradients(xi);
            for d in 0..2 {
                assert!(g.iter().map(|ga| ga[d]).sum::<f64>().abs() < 1e-13);
                let mut p = xi;
                let mut m = xi;
                p[d] += h;
                m[d] -= h;
                let (np, nm) = (Tri6::basis(p), Tri6::basis(m));
                for a in 0..6 {
                    let fd = (np[a] - nm[a]) / (2.0 * h);
                    assert!((fd - g[a][d]).abs() < 1e-8, "dN_{a}/dxi_{d}: {fd} vs {}", g[a][d]);
                }
            }
        }
    }

    #[test]
    fn tri6_edge_basis_is_the_trace_of_the_triangle_basis() {
        for s in [0.0, 0.13, 0.5, 0.77, 1.0] {
            let e = Tri6::edge_basis(s);
            let n = Tri6::basis([s, 0.0]); // edge 0→1 with mid node 3
            assert!((e[0] - n[0]).abs() < 1e-15 && (e[1] - n[1]).abs() < 1e-15 && (e[2] - n[3]).abs() < 1e-15);
        }
    }
}
