//! Hyperelastic energy densities `ψ(F)` per unit reference volume \[J/m³\], 2-D.
//!
//! `F` is stored as `vec(F) = [F₀₀, F₀₁, F₁₀, F₁₁]` (row-major, `F_ij = ∂x_i/∂X_j`); see [`VecF`].
//! `P = ∂ψ/∂F` (first Piola–Kirchhoff stress) and `A = ∂P/∂F` use the same ordering.
//!
//! * **Neo-Hookean (the tutorial's law)**, `k = λ/μ`, `J = det F`, `C = FᵀF`:
//!   ```text
//!   ψ = μ/2 (tr C − 2) + μ²/λ (J^(−k) − 1)          (= the tutorial's ψ minus its value at C = I)
//!   P = μ (F − J^(−k−1) cof F),   cof F = J F⁻ᵀ
//!   A = μ (I + (k+1) J^(−k−2) cof F ⊗ cof F − J^(−k−1) ∂cof F/∂F)
//!   σ = (μ/J) (F Fᵀ − J^(−k) I)
//!   ```
//!   The tutorial writes `ψ(C) = μ/2 (tr(C − I) + 2μ/λ det(C)^(−λ/2μ) − 1)`; since `det C = J²` the two
//!   differ only by the constant `μ²/λ − μ/2`, so forces are identical and `ψ(I) = 0` here.
//! * **St. Venant–Kirchhoff**, `E = (C − I)/2`: `ψ = λ/2 (tr E)² + μ tr(E²)`; `P` and `A` by
//!   automatic differentiation (second-order dual numbers, `num-dual`).
//!
//! Plane stress uses `λ* = Eν/(1 − ν²)`, plane strain `λ = Eν/((1 + ν)(1 − 2ν))`
//! ([`crate::config::Material::lame`]). An inadmissible state (`J ≤ 0`) has `ψ = +∞`, so the line
//! search of the Newton solver backs off from it.

use nalgebra::SVector;
use num_dual::{hessian, Dual2SVec64, DualNum};

use crate::config::{self, MaterialModel, Plane};

/// `vec(F) = [F₀₀, F₀₁, F₁₀, F₁₁]`, row-major.
pub type VecF = [f64; 4];

/// First Piola–Kirchhoff stress and its derivative, both in `vec(F)` order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StressTangent {
    /// `ψ(F)` \[J/m³\].
    pub energy: f64,
    /// `P = ∂ψ/∂F` \[Pa\].
    pub stress: [f64; 4],
    /// `A = ∂P/∂F` \[Pa\], `tangent[v][w] = ∂P_v/∂F_w`.
    pub tangent: [[f64; 4]; 4],
}

/// `det F`.
pub fn det<T: DualNum<Primitive = f64> + Copy>(f: &[T; 4]) -> T {
    f[0] * f[3] - f[1] * f[2]
}

/// `cof F = ∂(det F)/∂F = J F⁻ᵀ` in `vec` order.
pub fn cofactor(f: &VecF) -> VecF {
    [f[3], -f[2], -f[1], f[0]]
}

/// An isotropic hyperelastic law in 2-D.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Which energy.
    pub model: MaterialModel,
    /// Plane stress or strain (decides `λ` and the out-of-plane stress).
    pub plane: Plane,
    /// First Lamé parameter of the 2-D model \[Pa\].
    pub lambda: f64,
    /// Shear modulus \[Pa\].
    pub mu: f64,
}

impl Material {
    /// The law described by the configuration.
    pub fn from_config(m: &config::Material) -> Self {
        let (lambda, mu) = m.lame();
        Self {
            model: m.model,
            plane: m.plane,
            lambda,
            mu,
        }
    }

    /// `ψ(F)`, generic in the scalar so that it can be differentiated automatically.
    /// `+∞` (as a real number) for `J ≤ 0`.
    #[allow(non_snake_case)]
    pub fn energy_density<T: DualNum<Primitive = f64> + Copy>(&self, F: &[T; 4]) -> T {
        let J = det(F);
        if J.re() <= 0.0 {
            return T::from(f64::INFINITY);
        }
        let (lambda, mu) = (self.lambda, self.mu);
        // C = FᵀF
        let c00 = F[0] * F[0] + F[2] * F[2];
        let c11 = F[1] * F[1] + F[3] * F[3];
        let c01 = F[0] * F[1] + F[2] * F[3];
        match self.model {
            MaterialModel::NeoHookean => {
                let k = lambda / mu;
                (c00 + c11 - 2.0) * (0.5 * mu) + (J.powf(-k) - 1.0) * (mu * mu / lambda)
            }
            MaterialModel::SaintVenantKirchhoff => {
                let (e00, e11, e01) = ((c00 - 1.0) * 0.5, (c11 - 1.0) * 0.5, c01 * 0.5);
                let tr = e00 + e11;
                tr * tr * (0.5 * lambda) + (e00 * e00 + e11 * e11 + e01 * e01 * 2.0) * mu
            }
        }
    }

    /// `ψ`, `P`, `A` by automatic differentiation of [`Material::energy_density`].
    #[allow(non_snake_case)]
    pub fn stress_tangent_ad(&self, F: &VecF) -> StressTangent {
        let x = SVector::<f64, 4>::from(*F);
        let (energy, g, h) = hessian(
            |v: SVector<Dual2SVec64<4>, 4>| self.energy_density(&[v[0], v[1], v[2], v[3]]),
            &x,
        );
        let mut tangent = [[0.0; 4]; 4];
        for (v, row) in tangent.iter_mut().enumerate() {
            for (w, t) in row.iter_mut().enumerate() {
                *t = h[(v, w)];
            }
        }
        StressTangent {
            energy,
            stress: [g[0], g[1], g[2], g[3]],
            tangent,
        }
    }

    /// `ψ`, `P`, `A`: closed form for the Neo-Hookean law, automatic differentiation otherwise.
    /// For `J ≤ 0` the energy is `+∞` and stress and tangent are zero.
    #[allow(non_snake_case)]
    pub fn stress_tangent(&self, F: &VecF) -> StressTangent {
        let J = det(F);
        if J <= 0.0 {
            return StressTangent {
                energy: f64::INFINITY,
                stress: [0.0; 4],
                tangent: [[0.0; 4]; 4],
            };
        }
        match self.model {
            MaterialModel::NeoHookean => {
                let (lambda, mu) = (self.lambda, self.mu);
                let k = lambda / mu;
                let jk = J.powf(-k);
                let jk1 = jk / J; // J^(−k−1)
                let jk2 = jk1 / J; // J^(−k−2)
                let c = cofactor(F);
                let tr_c = F.iter().map(|x| x * x).sum::<f64>();
                let energy = 0.5 * mu * (tr_c - 2.0) + mu * mu / lambda * (jk - 1.0);
                let stress = [0, 1, 2, 3].map(|v| mu * (F[v] - jk1 * c[v]));
                let mut tangent = [[0.0; 4]; 4];
                let a = mu * (k + 1.0) * jk2;
                for v in 0..4 {
                    for w in 0..4 {
                        tangent[v][w] = a * c[v] * c[w];
                    }
                    tangent[v][v] += mu;
                }
                // ∂cof/∂F: cof = [F₁₁, −F₁₀, −F₀₁, F₀₀]
                let b = mu * jk1;
                tangent[0][3] -= b;
                tangent[3][0] -= b;
                tangent[1][2] += b;
                tangent[2][1] += b;
                StressTangent {
                    energy,
                    stress,
                    tangent,
                }
            }
            MaterialModel::SaintVenantKirchhoff => self.stress_tangent_ad(F),
        }
    }

    /// Cauchy stress `σ = J⁻¹ P Fᵀ` as `[σxx, σyy, σxy]` and the out-of-plane normal stress `σzz`
    /// (zero in plane stress; in plane strain the value that keeps `ε_zz = 0`) \[Pa\].
    #[allow(non_snake_case)]
    pub fn cauchy_stress(&self, F: &VecF) -> ([f64; 3], f64) {
        let J = det(F);
        if J <= 0.0 {
            return ([f64::NAN; 3], f64::NAN);
        }
        let P = self.stress_tangent(F).stress;
        // (P Fᵀ)_ij = Σ_K P_iK F_jK
        let s00 = (P[0] * F[0] + P[1] * F[1]) / J;
        let s11 = (P[2] * F[2] + P[3] * F[3]) / J;
        let s01 = (P[0] * F[2] + P[1] * F[3]) / J;
        let szz = match self.plane {
            Plane::Stress => 0.0,
            Plane::Strain => match self.model {
                // 3-D energies with F₃₃ = 1: S₃₃ = μ(1 − J^(−k)) resp. λ tr E, and σzz = S₃₃ / J.
                MaterialModel::NeoHookean => self.mu * (1.0 - J.powf(-self.lambda / self.mu)) / J,
                MaterialModel::SaintVenantKirchhoff => {
                    let tr_e = 0.5 * (F.iter().map(|x| x * x).sum::<f64>() - 2.0);
                    self.lambda * tr_e / J
                }
            },
        };
        ([s00, s11, s01], szz)
    }
}

/// Von Mises equivalent stress of `[σxx, σyy, σxy]` with out-of-plane `σzz` (`σxz = σyz = 0`):
/// `√(½((σxx−σyy)² + (σyy−σzz)² + (σzz−σxx)²) + 3σxy²)`; for `σzz = 0` the tutorial's
/// plane-stress formula `√(σxx² + σyy² − σxx σyy + 3σxy²)`.
pub fn von_mises(s: [f64; 3], szz: f64) -> f64 {
    let [sxx, syy, sxy] = s;
    (0.5 * ((sxx - syy).powi(2) + (syy - szz).powi(2) + (szz - sxx).powi(2)) + 3.0 * sxy * sxy).sqrt()
}
