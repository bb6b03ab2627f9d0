//! Measures of a [`Mesh`] over its isoparametric six-node elements: area, first and polar
//! moments, Jacobians and angles.
//!
//! Each element is the image of the reference triangle `T̂ = {ξ, η ≥ 0, ξ + η ≤ 1}` under the P2
//! map `x(ξ) = Σₐ Nₐ(ξ) xₐ`. With the Tri6 basis (`λ₀ = 1 − ξ − η`, `λ₁ = ξ`, `λ₂ = η`)
//!
//! ```text
//! N₀ = λ₀(2λ₀ − 1), N₁ = λ₁(2λ₁ − 1), N₂ = λ₂(2λ₂ − 1), N₃ = 4λ₀λ₁, N₄ = 4λ₁λ₂, N₅ = 4λ₂λ₀
//! ```
//!
//! `det J` is a polynomial of degree 2 and `∫ f dA = ∫_T̂ f(x(ξ)) det J dξ`, so the polar moment
//! integrand `|x|² det J` has degree 6. The rule used here is the collapsed (Duffy) product of
//! 5-point Gauss–Legendre rules, `ξ = u, η = v(1 − u)`, weight `wᵤ wᵥ (1 − u)`: exact for total
//! degree 8, enough for all three moments. It is private to the mesh module on purpose.

use super::Mesh;
use crate::element::Tri6;
use crate::geometry::Point;

const GL5: [(f64, f64); 5] = [
    (0.046_910_077_030_668, 0.118_463_442_528_094_54),
    (0.230_765_344_947_158_45, 0.239_314_335_249_683_23),
    (0.5, 0.284_444_444_444_444_44),
    (0.769_234_655_052_841_6, 0.239_314_335_249_683_23),
    (0.953_089_922_969_332, 0.118_463_442_528_094_54),
];

/// Points `(ξ, η)` and weights of the collapsed Gauss rule on the reference triangle (degree 8).
pub(crate) fn collapsed_rule() -> impl Iterator<Item = ([f64; 2], f64)> {
    GL5.into_iter().flat_map(|(u, wu)| {
        GL5.into_iter()
            .map(move |(v, wv)| ([u, v * (1.0 - u)], wu * wv * (1.0 - u)))
    })
}

impl Mesh {
    fn element_nodes(&self, t: usize) -> [Point; 6] {
        self.triangles[t].map(|n| self.nodes[n])
    }

    /// `det J` of element `t` at `(ξ, η)`.
    pub fn jacobian(&self, t: usize, xi: [f64; 2]) -> f64 {
        let (j, _) = crate::element::jacobian(&self.element_nodes(t), xi);
        j[0][0] * j[1][1] - j[0][1] * j[1][0]
    }

    /// Smallest `det J` of element `t` over its nodes and the points of a degree-8 rule.
    pub fn min_jacobian(&self, t: usize) -> f64 {
        const NODES: [[f64; 2]; 6] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]];
        let at_nodes = NODES.into_iter().map(|p| self.jacobian(t, p));
        let at_rule = collapsed_rule().map(|(p, _)| self.jacobian(t, p));
        at_nodes.chain(at_rule).fold(f64::INFINITY, f64::min)
    }

    /// `∫ f(x) dA` over the curved elements (collapsed Gauss, degree 8), summed with
    /// Kahan compensation.
    pub fn integrate(&self, f: impl Fn(Point) -> f64) -> f64 {
        let rule: Vec<([f64; 2], f64, [f64; 6])> = collapsed_rule().map(|(p, w)| (p, w, Tri6::basis(p))).collect();
        let (mut sum, mut comp) = (0.0, 0.0);
        for t in 0..self.triangles.len() {
            let x = self.element_nodes(t);
            let mut local = 0.0;
            for (p, w, n) in &rule {
                let mut q = [0.0; 2];
                for a in 0..6 {
                    q[0] += n[a] * x[a][0];
                    q[1] += n[a] * x[a][1];
                }
                local += w * f(q) * self.jacobian(t, *p);
            }
            let y = local - comp;
            let s = sum + y;
            comp = (s - sum) - y;
            sum = s;
        }
        sum
    }

    /// Area `∫ dA` \[m²\].
    pub fn area(&self) -> f64 {
        self.integrate(|_| 1.0)
    }

    /// First moments `(∫ x dA, ∫ y dA)` about the origin (the pivot) \[m³\].
    pub fn first_moment(&self) -> Point {
        [self.integrate(|p| p[0]), self.integrate(|p| p[1])]
    }

    /// Polar moment `∫ (x² + y²) dA` about the origin (the pivot) \[m⁴\].
    pub fn polar_moment(&self) -> f64 {
        self.integrate(|p| p[0] * p[0] + p[1] * p[1])
    }

    /// Smallest interior angle of the straight triangles through the vertices \[deg\].
    pub fn min_angle_deg(&self) -> f64 {
        let mut best = f64::INFINITY;
        for tri in &self.triangles {
            let p = [self.nodes[tri[0]], self.nodes[tri[1]], self.nodes[tri[2]]];
            for k in 0..3 {
                let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
                let u = [b[0] - a[0], b[1] - a[1]];
                let v = [c[0] - a[0], c[1] - a[1]];
                let ang = (u[0] * v[1] - u[1] * v[0]).atan2(u[0] * v[0] + u[1] * v[1]);
                best = best.min(ang.to_degrees());
            }
        }
        best
    }

    /// Number of boundary edges per name, in the order of [`Mesh::boundary_names`].
    pub fn boundary_edge_counts(&self) -> Vec<(String, usize)> {
        self.boundary_names
            .iter()
            .enumerate()
            .map(|(i, n)| (n.clone(), self.boundary_edges.iter().filter(|e| e.name == i).count()))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn factorial(n: u32) -> f64 {
        (1..=n).map(f64::from).product()
    }

    #[test]
    fn collapsed_rule_integrates_monomials_up_to_degree_8_exactly() {
        for p in 0..=8i32 {
            for q in 0..=(8 - p) {
                let approx: f64 = collapsed_rule().map(|(x, w)| w * x[0].powi(p) * x[1].powi(q)).sum();
                let exact = factorial(p as u32) * factorial(q as u32) / factorial((p + q + 2) as u32);
                assert!((approx - exact).abs() < 1e-15, "ξ^{p} η^{q}: {approx} vs {exact}");
            }
        }
    }

    #[test]
    fn tri6_basis_is_nodal_and_a_partition_of_unity() {
        let nodes = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]];
        for (i, p) in nodes.iter().enumerate() {
            let n = Tri6::basis(*p);
            for (j, v) in n.iter().enumerate() {
                assert!((v - if i == j { 1.0 } else { 0.0 }).abs() < 1e-15);
            }
            let g = Tri6::basis_gradients(*p);
            let s = g.iter().fold([0.0, 0.0], |acc, d| [acc[0] + d[0], acc[1] + d[1]]);
            assert!(s[0].abs() < 1e-14 && s[1].abs() < 1e-14);
        }
    }
}
