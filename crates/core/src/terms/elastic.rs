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
//!
//! **Discrete gradient** (the energy-momentum scheme): over a step from `u₀` to `u₁`, per quadrature
//! point, with `F_m = ½(F₀ + F₁)` and the discrete stress `S_d` of
//! [`Material::discrete_stress`] (Gonzalez 2000), plus the optional dissipative stress
//! `S_χ = (χ/2) (λ tr ΔE I + 2μ ΔE)`:
//!
//! ```text
//! g_ai = Σ_q w Σ_j (F_m (S_d + S_χ))_ij ∂N_a/∂X_j
//! ```
//!
//! Since `ΔE = ½(F_mᵀ ΔF + ΔFᵀ F_m)` exactly, `g · Δu = Σ_q w (S_d + S_χ) : ΔE
//! = Π(u₁) − Π(u₀) + Σ_q w (χ/2) ΔE : ℂ₀ : ΔE`: the elastic forces do the work of the change of
//! strain energy exactly, plus a non-negative dissipated part (`ℂ₀` the positive-definite
//! isotropic tensor of the Lamé constants). `F_m S F_mᵀ` is
//! symmetric, so the forces have no moment about the pivot at the mid-step positions: angular
//! momentum is conserved. A rigid rotation of any size leaves `E` and therefore `S_d` unchanged.

use std::sync::Arc;

use rayon::prelude::*;

use super::{StepContext, StepStart, Term};
use crate::assembly::{element_dofs, Pattern};
use crate::fe::FeCache;
use crate::material::{det, first_piola, green_strain, Material, StressTangent, Sym, VecF};
use crate::mesh::Mesh;

/// Elements per parallel block.
const BLOCK: usize = 1024;

/// Points per element of the degree-4 rule the bodies use ([`crate::quadrature::TriangleRule::degree4`]),
/// for which the kernels take an element's points side by side.
const POINTS: usize = 6;

/// Start-of-step values per quadrature point for the discrete gradient: `F₀` (4), `E₀` (3) and
/// `ψ(E₀)` with its rounding scale (2, [`Material::strain_energy`]).
const START: usize = 9;

/// The elastic strain energy of the whole body.
#[derive(Clone, Debug)]
pub struct Elastic {
    /// The constitutive law.
    pub material: Material,
    /// Element connectivity.
    pub triangles: Vec<[usize; 6]>,
    /// Reference data (degree-4 rule, weights carry the thickness), shared by the models of one
    /// mesh ([`crate::model::shared`]).
    pub cache: Arc<FeCache>,
    /// Index of the first element among the elements of the pattern it assembles into (a body
    /// after the first of a model starts after the elements of those before it).
    pub first_element: usize,
}

/// Element results: energy, gradient (12), Hessian (144, row-major).
struct ElementOut {
    energy: f64,
    g: [f64; 12],
    k: [f64; 144],
}

impl Elastic {
    /// Builds the term.
    pub fn new(material: Material, mesh: &Mesh, cache: impl Into<Arc<FeCache>>) -> Self {
        Self {
            material,
            triangles: mesh.triangles.clone(),
            cache: cache.into(),
            first_element: 0,
        }
    }

    /// `F` at quadrature point `q` of element `e`.
    #[inline]
    pub fn deformation_gradient(&self, e: usize, q: usize, u: &[f64]) -> VecF {
        let grads = &self.cache.grads[e * self.cache.points_per_element + q];
        deformation_gradient(&self.triangles[e], grads, u)
    }

    /// Energy (0 unless `with_energy`, `+∞` for an inverted element either way), gradient and
    /// tangent of one element.
    fn element(&self, e: usize, u: &[f64], with_energy: bool) -> ElementOut {
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
            } = self.material.stress_tangent_of(&f, with_energy);
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

    /// Energy (with `with_energy`; otherwise 0, or `+∞` for an inverted element) and gradient of
    /// one element (no tangent).
    fn element_gradient(&self, e: usize, u: &[f64], with_energy: bool) -> (f64, [f64; 12]) {
        let nq = self.cache.points_per_element;
        if !with_energy && nq == POINTS {
            return self.element_gradient_points(e, u);
        }
        let (mut energy, mut g) = (0.0, [0.0; 12]);
        for q in 0..nq {
            let grads = &self.cache.grads[e * nq + q];
            let w = self.cache.weights[e * nq + q];
            let f = deformation_gradient(&self.triangles[e], grads, u);
            let (psi, p) = match with_energy {
                true => self.material.stress(&f),
                // the same P without the energy's power function
                false if det(&f) > 0.0 => (0.0, self.material.first_piola_stress(&f)),
                false => (f64::INFINITY, [0.0; 4]),
            };
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

    /// Discrete gradient of one element over a step (see the module doc); returns 0, or `+∞` when
    /// an element is inverted at `u₁`.
    fn element_discrete(&self, e: usize, start: &[f64], u1: &[f64], chi: f64) -> (f64, [f64; 12]) {
        let nq = self.cache.points_per_element;
        if nq == POINTS {
            return self.element_discrete_points(e, start, u1, chi);
        }
        let m = &self.material;
        let mut g = [0.0; 12];
        for q in 0..nq {
            let k = e * nq + q;
            let grads = &self.cache.grads[k];
            let w = self.cache.weights[k];
            let f1 = deformation_gradient(&self.triangles[e], grads, u1);
            if det(&f1) <= 0.0 {
                return (f64::INFINITY, g);
            }
            let s0 = &start[k * START..(k + 1) * START];
            let e0 = [s0[4], s0[5], s0[6]];
            let e1 = green_strain(&f1);
            let mut s = m.discrete_stress(&e0, (s0[7], s0[8]), &e1);
            if chi > 0.0 {
                let de = [e1[0] - e0[0], e1[1] - e0[1], e1[2] - e0[2]];
                let (l, m2) = (0.5 * chi * m.lambda * (de[0] + de[1]), chi * m.mu);
                s[0] += l + m2 * de[0];
                s[1] += l + m2 * de[1];
                s[2] += m2 * de[2];
            }
            let fm = [0, 1, 2, 3].map(|i| 0.5 * (s0[i] + f1[i]));
            let p = first_piola(&fm, &s);
            for (n, gn) in grads.iter().enumerate() {
                g[2 * n] += w * (p[0] * gn[0] + p[1] * gn[1]);
                g[2 * n + 1] += w * (p[2] * gn[0] + p[3] * gn[1]);
            }
        }
        (0.0, g)
    }

    /// `F` at the [`POINTS`] points of element `e` ([`deformation_gradient`] at each, the same
    /// numbers), the element's displacements read once.
    #[inline]
    fn deformation_gradients(&self, e: usize, u: &[f64]) -> [VecF; POINTS] {
        let nodes = &self.triangles[e];
        let ue: [[f64; 2]; 6] = nodes.map(|n| [u[2 * n], u[2 * n + 1]]);
        std::array::from_fn(|q| {
            let grads = &self.cache.grads[e * POINTS + q];
            let mut f = [1.0, 0.0, 0.0, 1.0];
            for ([ux, uy], g) in ue.iter().zip(grads.iter()) {
                f[0] += ux * g[0];
                f[1] += ux * g[1];
                f[2] += uy * g[0];
                f[3] += uy * g[1];
            }
            f
        })
    }

    /// [`Elastic::element_gradient`] without the energy for an element of [`POINTS`] points, the
    /// points side by side through [`Material::first_piola_stresses`]; the same numbers bit for
    /// bit (an inverted element, `+∞`, with the gradient of its points before the first inverted
    /// one, as there).
    fn element_gradient_points(&self, e: usize, u: &[f64]) -> (f64, [f64; 12]) {
        let mut g = [0.0; 12];
        let f = self.deformation_gradients(e, u);
        let inverted = f.iter().position(|f| det(f) <= 0.0);
        let p = match inverted {
            None => self.material.first_piola_stresses(&f),
            Some(_) => [[0.0; 4]; POINTS],
        };
        for q in 0..POINTS {
            if inverted == Some(q) {
                return (f64::INFINITY, g);
            }
            let p = match inverted {
                None => p[q],
                Some(_) => self.material.first_piola_stress(&f[q]),
            };
            let grads = &self.cache.grads[e * POINTS + q];
            let w = self.cache.weights[e * POINTS + q];
            for (n, gn) in grads.iter().enumerate() {
                g[2 * n] += w * (p[0] * gn[0] + p[1] * gn[1]);
                g[2 * n + 1] += w * (p[2] * gn[0] + p[3] * gn[1]);
            }
        }
        (0.0, g)
    }

    /// [`Elastic::element_discrete`] for an element of [`POINTS`] points, the points side by side
    /// through [`Material::discrete_stresses`]; the same numbers bit for bit.
    fn element_discrete_points(&self, e: usize, start: &[f64], u1: &[f64], chi: f64) -> (f64, [f64; 12]) {
        let m = &self.material;
        let mut g = [0.0; 12];
        let k0 = e * POINTS;
        let f1 = self.deformation_gradients(e, u1);
        if f1.iter().any(|f| det(f) <= 0.0) {
            return (f64::INFINITY, g);
        }
        let s0 = |q: usize| &start[(k0 + q) * START..(k0 + q + 1) * START];
        let e0: [Sym; POINTS] = std::array::from_fn(|q| [s0(q)[4], s0(q)[5], s0(q)[6]]);
        let psi0: [(f64, f64); POINTS] = std::array::from_fn(|q| (s0(q)[7], s0(q)[8]));
        let e1 = f1.map(|f| green_strain(&f));
        let stresses = m.discrete_stresses(&e0, &psi0, &e1);
        for q in 0..POINTS {
            let grads = &self.cache.grads[k0 + q];
            let w = self.cache.weights[k0 + q];
            let mut s = stresses[q];
            if chi > 0.0 {
                let de = [e1[q][0] - e0[q][0], e1[q][1] - e0[q][1], e1[q][2] - e0[q][2]];
                let (l, m2) = (0.5 * chi * m.lambda * (de[0] + de[1]), chi * m.mu);
                s[0] += l + m2 * de[0];
                s[1] += l + m2 * de[1];
                s[2] += m2 * de[2];
            }
            let fm = [0, 1, 2, 3].map(|i| 0.5 * (s0(q)[i] + f1[q][i]));
            let p = first_piola(&fm, &s);
            for (n, gn) in grads.iter().enumerate() {
                g[2 * n] += w * (p[0] * gn[0] + p[1] * gn[1]);
                g[2 * n + 1] += w * (p[2] * gn[0] + p[3] * gn[1]);
            }
        }
        (0.0, g)
    }

    /// Runs an element kernel returning `(energy, gradient)` over all elements in parallel blocks
    /// and adds `factor` times the gradients into `g` in element order; returns the energy.
    fn gather(&self, factor: f64, g: &mut [f64], kernel: impl Fn(usize) -> (f64, [f64; 12]) + Sync) -> f64 {
        let ne = self.triangles.len();
        let mut energy = 0.0;
        let mut buffer: Vec<(f64, [f64; 12])> = Vec::new();
        let mut start = 0;
        while start < ne {
            let end = (start + 4 * BLOCK).min(ne);
            buffer.clear();
            (start..end).into_par_iter().map(&kernel).collect_into_vec(&mut buffer);
            for (i, (psi, ge)) in buffer.iter().enumerate() {
                energy += psi;
                for (d, gv) in element_dofs(&self.triangles[start + i]).iter().zip(ge.iter()) {
                    g[*d] += factor * gv;
                }
            }
            start = end;
        }
        energy
    }

    /// Energy and gradient of the whole body, `g += ∂Π/∂u`.
    fn run_gradient(&self, u: &[f64], g: &mut [f64], with_energy: bool) -> f64 {
        self.gather(1.0, g, |e| self.element_gradient(e, u, with_energy))
    }

    /// Tangent of the whole body, and with `g` its energy and gradient (without `g` the returned
    /// energy is 0, or `+∞` where an element is inverted: the Hessian alone skips the energy).
    fn run(&self, u: &[f64], mut g: Option<&mut [f64]>, pattern: &Pattern, values: &mut [f64]) -> f64 {
        let ne = self.triangles.len();
        let with_energy = g.is_some();
        let mut energy = 0.0;
        let mut buffer: Vec<ElementOut> = Vec::new();
        let mut start = 0;
        while start < ne {
            let end = (start + BLOCK).min(ne);
            buffer.clear();
            (start..end)
                .into_par_iter()
                .map(|e| self.element(e, u, with_energy))
                .collect_into_vec(&mut buffer);
            for (i, out) in buffer.iter().enumerate() {
                let e = start + i;
                energy += out.energy;
                if let Some(g) = g.as_deref_mut() {
                    for (d, gv) in element_dofs(&self.triangles[e]).iter().zip(out.g.iter()) {
                        g[*d] += gv;
                    }
                }
                pattern.scatter_element(self.first_element + e, &out.k, values);
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

/// The displacement gradient `H = ∇₀u = Σ_a u_a ⊗ ∇₀N_a` for one element (`F − I` without the
/// rounding of a difference of numbers near 1).
pub fn displacement_gradient(nodes: &[usize; 6], grads: &[[f64; 2]; 6], u: &[f64]) -> VecF {
    nodes.iter().zip(grads).fold([0.0; 4], |h, (n, g)| {
        let (ux, uy) = (u[2 * n], u[2 * n + 1]);
        [h[0] + ux * g[0], h[1] + ux * g[1], h[2] + uy * g[0], h[3] + uy * g[1]]
    })
}

impl Elastic {
    /// The start data of a discrete gradient ([`Term::discrete_start`]): `F`, `E` and `ψ(E)` at
    /// every quadrature point of `u0`.
    fn start_data(&self, u0: &[f64]) -> Vec<f64> {
        let nq = self.cache.points_per_element;
        let mut out = vec![0.0; self.cache.weights.len() * START];
        out.par_chunks_mut(nq * START).enumerate().for_each(|(e, chunk)| {
            if nq == POINTS {
                // the element's points side by side (Material::strain_energies)
                let f = self.deformation_gradients(e, u0);
                let e0 = f.map(|f| green_strain(&f));
                let psi = self.material.strain_energies(&e0);
                for (q, c) in chunk.chunks_exact_mut(START).enumerate() {
                    c[..4].copy_from_slice(&f[q]);
                    c[4..7].copy_from_slice(&e0[q]);
                    c[7..9].copy_from_slice(&[psi[q].0, psi[q].1]);
                }
                return;
            }
            for q in 0..nq {
                let f = self.deformation_gradient(e, q, u0);
                let c = &mut chunk[q * START..(q + 1) * START];
                let e0 = green_strain(&f);
                let (psi, scale) = self.material.strain_energy(&e0);
                c[..4].copy_from_slice(&f);
                c[4..7].copy_from_slice(&e0);
                c[7..9].copy_from_slice(&[psi, scale]);
            }
        });
        out
    }
}

impl Elastic {
    /// The strain energy of the state whose start data ([`Term::discrete_start`]) is `data`:
    /// `Σ_e Σ_q w ψ(E)`, summed as [`Term::energy`] sums it, so the same number bit for bit
    /// (`+∞` where an element is inverted).
    pub fn energy_of_start(&self, data: &[f64]) -> f64 {
        let nq = self.cache.points_per_element;
        data.chunks_exact(nq * START)
            .enumerate()
            .map(|(e, chunk)| {
                let mut s = 0.0;
                for (q, c) in chunk.chunks_exact(START).enumerate() {
                    let f = [c[0], c[1], c[2], c[3]];
                    let psi = if det(&f) <= 0.0 { f64::INFINITY } else { c[7] };
                    s += self.cache.weights[e * nq + q] * psi;
                }
                s
            })
            .sum()
    }
}

impl Term for Elastic {
    fn name(&self) -> &'static str {
        "elastic"
    }

    /// Element energies in parallel, summed in element order: rayon's parallel `sum` associates
    /// the terms as its work stealing happens to split them, which made the strain energy (and the
    /// line search that compares energies) differ in the last bits from run to run.
    fn energy(&self, u: &[f64], _cx: &StepContext) -> f64 {
        let nq = self.cache.points_per_element;
        let mut energies = Vec::with_capacity(self.triangles.len());
        (0..self.triangles.len())
            .into_par_iter()
            .map(|e| {
                let mut s = 0.0;
                for q in 0..nq {
                    let f = self.deformation_gradient(e, q, u);
                    s += self.cache.weights[e * nq + q] * self.material.energy(&f);
                }
                s
            })
            .collect_into_vec(&mut energies);
        energies.iter().sum()
    }

    fn add_gradient(&self, u: &[f64], _cx: &StepContext, g: &mut [f64]) {
        self.run_gradient(u, g, false);
    }

    fn energy_gradient(&self, u: &[f64], _cx: &StepContext, g: &mut [f64]) -> f64 {
        self.run_gradient(u, g, true)
    }

    fn add_hessian(&self, u: &[f64], _cx: &StepContext, pattern: &Pattern, values: &mut [f64]) {
        self.run(u, None, pattern, values);
    }

    fn assemble(&self, u: &[f64], _cx: &StepContext, pattern: &Pattern, g: &mut [f64], values: &mut [f64]) -> f64 {
        self.run(u, Some(g), pattern, values)
    }

    /// Per quadrature point `F₀`, `E₀` and `ψ(E₀)`.
    fn discrete_start(&self, cx: &StepContext) -> Vec<f64> {
        self.start_data(cx.u0)
    }

    fn add_discrete_gradient(
        &self,
        start: &StepStart,
        u1: &[f64],
        _cx: &StepContext,
        factor: f64,
        g: &mut [f64],
    ) -> f64 {
        let data = if start.data.len() == self.cache.weights.len() * START {
            std::borrow::Cow::Borrowed(start.data)
        } else {
            std::borrow::Cow::Owned(self.start_data(start.u))
        };
        let chi = start.dissipation;
        self.gather(factor, g, |e| self.element_discrete(e, &data, u1, chi))
    }
}
