//! Hyperelastic strain energy `Π_el(u) = ∫_Ω₀ ψ(F) t dA`, `F = I + ∇₀u`.
//!
//! With `B_a` the gradient of the basis function of node `a` (from [`crate::fe::FeCache`]),
//! `F_ij = δ_ij + Σ_a u_{a,i} ∂N_a/∂X_j`, and per quadrature point of weight `w` (thickness included):
//!
//! ```text
//! Π_e   = Σ_q w ψ(F)
//! g_ai  = Σ_q w Σ_j P_ij ∂N_a/∂X_j
//! K_aibk = Σ_q w Σ_jl A_ijkl ∂N_a/∂X_j ∂N_b/∂X_l
//! ```
//!
//! Element contributions are computed in parallel (rayon) in blocks and scattered serially into the
//! fixed pattern, so the result does not depend on the number of threads.

use rayon::prelude::*;

use super::Term;
use crate::assembly::{element_dofs, Pattern};
use crate::fe::FeCache;
use crate::material::{Material, StressTangent, VecF};
use crate::Mesh;

/// Elements per parallel block.
const BLOCK: usize = 1024;

/// The elastic strain energy of the whole body.
#[derive(Clone, Debug)]
pub struct Elastic {
    /// The constitutive law.
    pub material: Material,
    /// Element connectivity.
    pub triangles: Vec<[usize; 6]>,
    /// Reference data (degree-4 rule, weights carry the thickness).
    pub cache: FeCache,
}

/// Element results: energy, gradient (12), Hessian (144, row-major).
struct ElementOut {
    energy: f64,
    g: [f64; 12],
    k: [f64; 144],
}

impl Elastic {
    /// Builds the term.
    pub fn new(material: Material, mesh: &Mesh, cache: FeCache) -> Self {
        Self {
            material,
            triangles: mesh.triangles.clone(),
            cache,
        }
    }

    /// `F` at quadrature point `q` of element `e`.
    #[inline]
    pub fn deformation_gradient(&self, e: usize, q: usize, u: &[f64]) -> VecF {
        let grads = &self.cache.grads[e * self.cache.points_per_element + q];
        deformation_gradient(&self.triangles[e], grads, u)
    }

    /// Energy, gradient and tangent of one element.
    fn element(&self, e: usize, u: &[f64]) -> ElementOut {
        let nq = self.cache.points_per_element;
        let mut out = ElementOut {
            energy: 0.0,
            g: [0.0; 12],
            k: [0.0; 144],
        };
        for q in 0..nq {
            let grads = &self.cache.grads[e * nq + q];
            let w = self.cache.weights[e * nq + q];
            let f = deformation_gradient(&self.triangles[e], grads, u);
            let StressTangent {
                energy,
                stress: p,
                tangent: a,
            } = self.material.stress_tangent(&f);
            if !energy.is_finite() {
                out.energy = f64::INFINITY;
                return out;
            }
            out.energy += w * energy;
            for (n, gn) in grads.iter().enumerate() {
                for i in 0..2 {
                    out.g[2 * n + i] += w * (p[2 * i] * gn[0] + p[2 * i + 1] * gn[1]);
                }
            }
            // AB[v][2b+k] = Σ_l A[v][2k+l] ∂N_b/∂X_l
            let mut ab = [[0.0; 12]; 4];
            for (v, abv) in ab.iter_mut().enumerate() {
                for (b, gb) in grads.iter().enumerate() {
                    for k in 0..2 {
                        abv[2 * b + k] = a[v][2 * k] * gb[0] + a[v][2 * k + 1] * gb[1];
                    }
                }
            }
            for (n, gn) in grads.iter().enumerate() {
                for i in 0..2 {
                    let row = &mut out.k[(2 * n + i) * 12..(2 * n + i + 1) * 12];
                    let (r0, r1) = (&ab[2 * i], &ab[2 * i + 1]);
                    let (w0, w1) = (w * gn[0], w * gn[1]);
                    for c in 0..12 {
                        row[c] += w0 * r0[c] + w1 * r1[c];
                    }
                }
            }
        }
        out
    }

    /// Energy and gradient of one element (no tangent).
    fn element_gradient(&self, e: usize, u: &[f64]) -> (f64, [f64; 12]) {
        let nq = self.cache.points_per_element;
        let (mut energy, mut g) = (0.0, [0.0; 12]);
        for q in 0..nq {
            let grads = &self.cache.grads[e * nq + q];
            let w = self.cache.weights[e * nq + q];
            let f = deformation_gradient(&self.triangles[e], grads, u);
            let (psi, p) = self.material.stress(&f);
            if !psi.is_finite() {
                return (f64::INFINITY, g);
            }
            energy += w * psi;
            for (n, gn) in grads.iter().enumerate() {
                g[2 * n] += w * (p[0] * gn[0] + p[1] * gn[1]);
                g[2 * n + 1] += w * (p[2] * gn[0] + p[3] * gn[1]);
            }
        }
        (energy, g)
    }

    /// Energy and gradient of the whole body, `g += ∂Π/∂u`.
    fn run_gradient(&self, u: &[f64], g: &mut [f64]) -> f64 {
        let ne = self.triangles.len();
        let mut energy = 0.0;
        let mut buffer: Vec<(f64, [f64; 12])> = Vec::new();
        let mut start = 0;
        while start < ne {
            let end = (start + 4 * BLOCK).min(ne);
            buffer.clear();
            (start..end)
                .into_par_iter()
                .map(|e| self.element_gradient(e, u))
                .collect_into_vec(&mut buffer);
            for (i, (psi, ge)) in buffer.iter().enumerate() {
                energy += psi;
                for (d, gv) in element_dofs(&self.triangles[start + i]).iter().zip(ge.iter()) {
                    g[*d] += gv;
                }
            }
            start = end;
        }
        energy
    }

    /// Energy and tangent (and the gradient when `g` is given) of the whole body.
    fn run(&self, u: &[f64], mut g: Option<&mut [f64]>, pattern: &Pattern, values: &mut [f64]) -> f64 {
        let ne = self.triangles.len();
        let mut energy = 0.0;
        let mut buffer: Vec<ElementOut> = Vec::new();
        let mut start = 0;
        while start < ne {
            let end = (start + BLOCK).min(ne);
            buffer.clear();
            (start..end)
                .into_par_iter()
                .map(|e| self.element(e, u))
                .collect_into_vec(&mut buffer);
            for (i, out) in buffer.iter().enumerate() {
                let e = start + i;
                energy += out.energy;
                if let Some(g) = g.as_deref_mut() {
                    for (d, gv) in element_dofs(&self.triangles[e]).iter().zip(out.g.iter()) {
                        g[*d] += gv;
                    }
                }
                pattern.scatter_element(e, &out.k, values);
            }
            start = end;
        }
        energy
    }
}

/// `F = I + Σ_a u_a ⊗ ∇₀N_a` for one element.
#[inline]
pub fn deformation_gradient(nodes: &[usize; 6], grads: &[[f64; 2]; 6], u: &[f64]) -> VecF {
    let mut f = [1.0, 0.0, 0.0, 1.0];
    for (n, g) in nodes.iter().zip(grads.iter()) {
        let (ux, uy) = (u[2 * n], u[2 * n + 1]);
        f[0] += ux * g[0];
        f[1] += ux * g[1];
        f[2] += uy * g[0];
        f[3] += uy * g[1];
    }
    f
}

impl Term for Elastic {
    fn name(&self) -> &'static str {
        "elastic"
    }

    fn energy(&self, u: &[f64], _t: f64) -> f64 {
        let nq = self.cache.points_per_element;
        (0..self.triangles.len())
            .into_par_iter()
            .map(|e| {
                let mut s = 0.0;
                for q in 0..nq {
                    let f = self.deformation_gradient(e, q, u);
                    s += self.cache.weights[e * nq + q] * self.material.energy_density(&f);
                }
                s
            })
            .sum()
    }

    fn add_gradient(&self, u: &[f64], _t: f64, g: &mut [f64]) {
        self.run_gradient(u, g);
    }

    fn energy_gradient(&self, u: &[f64], _t: f64, g: &mut [f64]) -> f64 {
        self.run_gradient(u, g)
    }

    fn add_hessian(&self, u: &[f64], _t: f64, pattern: &Pattern, values: &mut [f64]) {
        self.run(u, None, pattern, values);
    }

    fn assemble(&self, u: &[f64], _t: f64, pattern: &Pattern, g: &mut [f64], values: &mut [f64]) -> f64 {
        self.run(u, Some(g), pattern, values)
    }
}
