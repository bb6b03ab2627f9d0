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

mod points;
pub use points::Power;

/// `vec(F) = [F₀₀, F₀₁, F₁₀, F₁₁]`, row-major.
pub type VecF = [f64; 4];

/// A symmetric 2-D tensor `[T₀₀, T₁₁, T₀₁]` (Green–Lagrange strain, second Piola–Kirchhoff stress).
pub type Sym = [f64; 3];

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

/// Green–Lagrange strain `E = ½(FᵀF − I)` of `F`, formed from `H = F − I` as
/// `E = ½(H + Hᵀ + HᵀH)` so that no entry is a difference of numbers near 1.
pub fn green_strain(f: &VecF) -> Sym {
    let h = [f[0] - 1.0, f[1], f[2], f[3] - 1.0];
    [
        h[0] + 0.5 * (h[0] * h[0] + h[2] * h[2]),
        h[3] + 0.5 * (h[1] * h[1] + h[3] * h[3]),
        0.5 * (h[1] + h[2] + h[0] * h[1] + h[2] * h[3]),
    ]
}

/// `(tr E, det C − 1)` of a strain, `det C − 1 = 2 tr E + 4 det E` (`C = I + 2E`), without
/// forming `C`.
pub(crate) fn invariants(e: &Sym) -> (f64, f64) {
    let tr = e[0] + e[1];
    (tr, 2.0 * tr + 4.0 * (e[0] * e[1] - e[2] * e[2]))
}

/// `A : B = Σ_ij A_ij B_ij` of two symmetric tensors (the off-diagonal entry counts twice).
pub fn sym_dot(a: &Sym, b: &Sym) -> f64 {
    a[0] * b[0] + a[1] * b[1] + 2.0 * a[2] * b[2]
}

/// `P = F S` (first from second Piola–Kirchhoff stress) in `vec` order.
pub fn first_piola(f: &VecF, s: &Sym) -> [f64; 4] {
    [
        f[0] * s[0] + f[1] * s[2],
        f[0] * s[2] + f[1] * s[1],
        f[2] * s[0] + f[3] * s[2],
        f[2] * s[2] + f[3] * s[1],
    ]
}

/// `(1 + x)^a − 1` without cancellation for small `x` and, for `|x| < 10⁻³`, without a
/// transcendental function: the binomial series to `x⁶`, whose remainder is below
/// `|C(a, 7)| 10⁻²¹` relative (the strains of a steel pendulum are `10⁻⁷`); otherwise
/// `expm1(a ln1p(x))`.
#[inline]
pub fn pow1p_minus_1(x: f64, a: f64) -> f64 {
    Power::new(a).minus_1(x)
}

/// Multiple of the machine epsilon in the rounding bound of the discrete stress's correction
/// ([`Material::discrete_stress`]).
const DISCRETE_ROUNDING: f64 = 64.0;

/// Size of a strain increment `|E₁ − E₀|` (Frobenius) below which [`Material::discrete_stress`]
/// takes its correction from the Taylor series.
const TAYLOR_LIMIT: f64 = 1e-4;

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
    /// `k = λ/μ`.
    k: f64,
    /// `μ/k`.
    mu_over_k: f64,
    /// Neo-Hookean: `(det C)^(−k/2)` (the energy), `(det C)^(−k/2 − 1)` (the second Piola–Kirchhoff
    /// stress) and `J^(−k)` (the first Piola–Kirchhoff and Cauchy stresses), less 1.
    powers: [Power; 3],
}

impl Material {
    /// The law described by the configuration.
    pub fn from_config(m: &config::Material) -> Self {
        let (lambda, mu) = m.lame();
        let k = lambda / mu;
        Self {
            model: m.model,
            plane: m.plane,
            lambda,
            mu,
            k,
            mu_over_k: mu / k,
            powers: [Power::new(-0.5 * k), Power::new(-(0.5 * k + 1.0)), Power::new(-k)],
        }
    }

    /// `ψ` as a function of the Green–Lagrange strain `E` (with `det C > 0`), together with the
    /// sum of the magnitudes of the terms it adds up (the scale of its rounding error) \[J/m³\].
    ///
    /// Neo-Hookean, with `C = I + 2E`, `det C = 1 + x`, `x = 2 tr E + 4 det E`, `k = λ/μ`:
    /// `ψ = μ tr E + (μ/k) expm1(−(k/2) ln1p(x))`, which is the closed form of the module doc
    /// written without differences of numbers near 1: its terms are of the size of the strain,
    /// so the rounding error of `ψ` is `ε μ |tr E|`, not `ε μ` (for steel at a strain of 1e-7 the
    /// energy density is 1e-3 J/m³ and the textbook form has an absolute error of 1e-5).
    #[inline]
    pub fn strain_energy(&self, e: &Sym) -> (f64, f64) {
        let (tr, x) = invariants(e);
        match self.model {
            MaterialModel::NeoHookean => {
                let mu = self.mu;
                let second = self.mu_over_k * self.powers[0].minus_1(x);
                (mu * tr + second, (mu * tr).abs() + second.abs())
            }
            MaterialModel::SaintVenantKirchhoff => {
                let psi = 0.5 * self.lambda * tr * tr + self.mu * sym_dot(e, e);
                (psi, psi)
            }
        }
    }

    /// Second Piola–Kirchhoff stress `S = ∂ψ/∂E` \[Pa\] (with `det C > 0`).
    ///
    /// Neo-Hookean: `S = μ (I − J^(−k) C⁻¹)`, `J^(−k) C⁻¹ = d adj C`, `d = (det C)^(−k/2 − 1)`;
    /// St. Venant–Kirchhoff: `S = λ tr E I + 2μ E`.
    pub fn second_piola(&self, e: &Sym) -> Sym {
        self.second_piola_parts(e).0
    }

    /// [`Material::second_piola`] and, for the Neo-Hookean law, `(d, det C)` (`(0, 1)` otherwise).
    #[inline]
    fn second_piola_parts(&self, e: &Sym) -> (Sym, f64, f64) {
        let (tr, x) = invariants(e);
        match self.model {
            MaterialModel::NeoHookean => {
                let mu = self.mu;
                let d_minus_1 = self.powers[1].minus_1(x);
                let d = 1.0 + d_minus_1;
                // S₀₀ = μ(1 − d C₁₁) = μ(−(d − 1) − 2 d E₁₁), likewise S₁₁; S₀₁ = μ d C₀₁ = 2 μ d E₀₁
                let s = [
                    mu * (-d_minus_1 - 2.0 * d * e[1]),
                    mu * (-d_minus_1 - 2.0 * d * e[0]),
                    2.0 * mu * d * e[2],
                ];
                (s, d, 1.0 + x)
            }
            MaterialModel::SaintVenantKirchhoff => {
                let (l, m2) = (self.lambda * tr, 2.0 * self.mu);
                ([l + m2 * e[0], l + m2 * e[1], m2 * e[2]], 0.0, 1.0)
            }
        }
    }

    /// The discrete stress of Gonzalez (2000) between two strains: with `E_m = ½(E₀ + E₁)`,
    /// `D = E₁ − E₀`,
    ///
    /// ```text
    /// S_d = S(E_m) + N / (D:D) D,   N = ψ(E₁) − ψ(E₀) − S(E_m):D,   so that   S_d : D = ψ(E₁) − ψ(E₀).
    /// ```
    ///
    /// It depends on the strains only, so it is objective. `N` is of third order in `D`. For
    /// `|D| ≥ 10⁻⁴` it is computed as written; when it is then below its own rounding error
    /// (`64 ε` times the magnitudes it is made of) the correction is left out, since it would only
    /// amplify rounding. For `|D| < 10⁻⁴` (every strain increment of a steel pendulum) the
    /// difference would be all rounding, and `N` is taken from its Taylor series about `E_m`,
    /// `N = ψ'''(E_m)[D, D, D]/24 + ψ⁽⁵⁾(E_m)[D,…]/1920 + …`, of which the first term is kept: the
    /// neglected part is below `10⁻¹⁰ |N|`, far below rounding. For the St. Venant–Kirchhoff law `ψ` is
    /// quadratic in `E` and `N = 0`. For the Neo-Hookean law, along `E(s) = E_m + s D`,
    /// `det C = 1 + x(s)`, `x = x_m + s x₁ + s² x₂` with `x₁ = 2 tr D + 4 (E₀₀D₁₁ + E₁₁D₀₀ − 2E₀₁D₀₁)`,
    /// `x₂ = 4 det D`, and with `p = k/2`, `w = 1/(1 + x_m)`, `d = (1 + x_m)^(−p−1)`:
    /// `ψ''' = (μ/2)(p + 1) d w x₁ (6 x₂ − (p + 2) w x₁²)`.
    ///
    /// `psi0` is `ψ(E₀)` as [`Material::strain_energy`] returns it (value and rounding scale):
    /// the start of a step is the same for all its Newton iterations, so the caller computes it
    /// once per step; for a strained soft body the energy's power function is a third of the
    /// stress's cost.
    pub fn discrete_stress(&self, e0: &Sym, psi0: (f64, f64), e1: &Sym) -> Sym {
        let em = [0.5 * (e0[0] + e1[0]), 0.5 * (e0[1] + e1[1]), 0.5 * (e0[2] + e1[2])];
        let de = [e1[0] - e0[0], e1[1] - e0[1], e1[2] - e0[2]];
        let (mut s, d, det_c) = self.second_piola_parts(&em);
        let norm2 = sym_dot(&de, &de);
        if norm2 == 0.0 {
            return s;
        }
        let numerator = if norm2 >= TAYLOR_LIMIT * TAYLOR_LIMIT {
            let psi1 = self.strain_energy(e1);
            let work = sym_dot(&s, &de);
            let numerator = psi1.0 - psi0.0 - work;
            let size = psi0.1 + psi1.1 + (s[0] * de[0]).abs() + (s[1] * de[1]).abs() + 2.0 * (s[2] * de[2]).abs();
            if numerator.abs() <= DISCRETE_ROUNDING * f64::EPSILON * size {
                return s;
            }
            numerator
        } else {
            match self.model {
                MaterialModel::NeoHookean => self.taylor_term(&em, &de, d, 1.0 / det_c),
                MaterialModel::SaintVenantKirchhoff => 0.0,
            }
        };
        let c = numerator / norm2;
        for i in 0..3 {
            s[i] += c * de[i];
        }
        s
    }

    /// The first term of the Neo-Hookean `N`'s Taylor series in [`Material::discrete_stress`],
    /// `ψ'''(E_m)[D, D, D]/24`, at the mid-step strain `em` and the increment `de`, with `d` and
    /// `w = 1/(1 + x_m)` of `em` (one formula for the point-by-point and the batched stress).
    #[inline]
    pub(crate) fn taylor_term(&self, em: &Sym, de: &Sym, d: f64, w: f64) -> f64 {
        let p = 0.5 * self.k;
        let x1 = 2.0 * (de[0] + de[1]) + 4.0 * (em[0] * de[1] + em[1] * de[0] - 2.0 * em[2] * de[2]);
        let x2 = 4.0 * (de[0] * de[1] - de[2] * de[2]);
        let third = 0.5 * self.mu * (p + 1.0) * d * w * x1 * (6.0 * x2 - (p + 2.0) * w * x1 * x1);
        third / 24.0
    }

    /// `ψ(F)` for a real `F`, through [`Material::strain_energy`]; `+∞` for `J ≤ 0`.
    #[allow(non_snake_case)]
    pub fn energy(&self, F: &VecF) -> f64 {
        if det(F) <= 0.0 {
            return f64::INFINITY;
        }
        self.strain_energy(&green_strain(F)).0
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
        self.stress_tangent_of(F, true)
    }

    /// [`Material::stress_tangent`], with the energy left at 0 for an admissible `F` unless
    /// `with_energy` (a Hessian alone does not need it, and for the Neo-Hookean law it costs a
    /// power function of its own).
    #[allow(non_snake_case)]
    pub fn stress_tangent_of(&self, F: &VecF, with_energy: bool) -> StressTangent {
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
                let jk = 1.0 + self.powers[2].minus_1(J - 1.0);
                let jk1 = jk / J; // J^(−k−1)
                let jk2 = jk1 / J; // J^(−k−2)
                let c = cofactor(F);
                let energy = if with_energy {
                    self.strain_energy(&green_strain(F)).0
                } else {
                    0.0
                };
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
            MaterialModel::SaintVenantKirchhoff => StressTangent {
                energy: self.strain_energy(&green_strain(F)).0,
                ..self.stress_tangent_ad(F)
            },
        }
    }

    /// `ψ` and `P` without the tangent (closed form for Neo-Hookean).
    #[allow(non_snake_case)]
    pub fn stress(&self, F: &VecF) -> (f64, [f64; 4]) {
        if det(F) <= 0.0 {
            return (f64::INFINITY, [0.0; 4]);
        }
        let e = green_strain(F);
        (self.strain_energy(&e).0, self.first_piola_of(F, &e))
    }

    /// `P = ∂ψ/∂F` \[Pa\] for an admissible `F` (`det F > 0`), as [`Material::stress`] gives it.
    #[allow(non_snake_case)]
    pub fn first_piola_stress(&self, F: &VecF) -> [f64; 4] {
        self.first_piola_of(F, &green_strain(F))
    }

    /// `P` for an admissible `F` with its strain `e`: `μ (F − J^(−k−1) cof F)` (Neo-Hookean),
    /// `F S(E)` (St. Venant–Kirchhoff).
    #[allow(non_snake_case)]
    fn first_piola_of(&self, F: &VecF, e: &Sym) -> [f64; 4] {
        match self.model {
            MaterialModel::NeoHookean => {
                let J = det(F);
                let mu = self.mu;
                let jk1 = (1.0 + self.powers[2].minus_1(J - 1.0)) / J;
                let c = cofactor(F);
                [0, 1, 2, 3].map(|v| mu * (F[v] - jk1 * c[v]))
            }
            MaterialModel::SaintVenantKirchhoff => first_piola(F, &self.second_piola(e)),
        }
    }

    /// The small-strain law: the derivative of [`Material::cauchy_stress`] at rest (`F = I`),
    /// `d[σxx, σyy, σxy, σzz]/dH` \[Pa\] with `H = F − I` as `[H₀₀, H₀₁, H₁₀, H₁₁]`, row `c` the
    /// stress component, column `k` the gradient component. Central differences at
    /// `H = ±10⁻⁶ e_k`: the laws are evaluated without differences of numbers near 1, so their
    /// rounding stays relative to the stress itself, and the truncation error is of the order of
    /// `10⁻¹²` of the slope. The stress of a small displacement `u` is then `D H(u)`, linear in `u`.
    pub fn stress_slope_at_rest(&self) -> [[f64; 4]; 4] {
        const H: f64 = 1e-6;
        let mut d = [[0.0; 4]; 4];
        for k in 0..4 {
            let at = |sign: f64| {
                let mut f = [1.0, 0.0, 0.0, 1.0];
                f[k] += sign * H;
                let (s, szz) = self.cauchy_stress(&f);
                [s[0], s[1], s[2], szz]
            };
            let (plus, minus) = (at(1.0), at(-1.0));
            for c in 0..4 {
                d[c][k] = (plus[c] - minus[c]) / (2.0 * H);
            }
        }
        d
    }

    /// Cauchy stress `σ = J⁻¹ P Fᵀ` as `[σxx, σyy, σxy]` and the out-of-plane normal stress `σzz`
    /// (zero in plane stress; in plane strain the value that keeps `ε_zz = 0`) \[Pa\].
    #[allow(non_snake_case)]
    pub fn cauchy_stress(&self, F: &VecF) -> ([f64; 3], f64) {
        let J = det(F);
        if J <= 0.0 {
            return ([f64::NAN; 3], f64::NAN);
        }
        let [s00, s11, s01] = match self.model {
            MaterialModel::NeoHookean => {
                // σ = (μ/J)(F Fᵀ − J^(−k) I), the diagonal as (B_ii − 1) − (J^(−k) − 1) with
                // B₀₀ − 1 = h₀(2 + h₀) + F₀₁², h₀ = F₀₀ − 1 (likewise B₁₁): no difference of
                // numbers near 1
                let c = self.mu / J;
                let jk_1 = self.powers[2].minus_1(J - 1.0);
                let (h0, h3) = (F[0] - 1.0, F[3] - 1.0);
                [
                    c * (h0 * (2.0 + h0) + F[1] * F[1] - jk_1),
                    c * (h3 * (2.0 + h3) + F[2] * F[2] - jk_1),
                    c * (F[0] * F[2] + F[1] * F[3]),
                ]
            }
            MaterialModel::SaintVenantKirchhoff => {
                let P = self.first_piola_of(F, &green_strain(F));
                // (P Fᵀ)_ij = Σ_K P_iK F_jK
                [
                    (P[0] * F[0] + P[1] * F[1]) / J,
                    (P[2] * F[2] + P[3] * F[3]) / J,
                    (P[0] * F[2] + P[1] * F[3]) / J,
                ]
            }
        };
        let szz = match self.plane {
            Plane::Stress => 0.0,
            Plane::Strain => match self.model {
                // 3-D energies with F₃₃ = 1: S₃₃ = μ(1 − J^(−k)) resp. λ tr E, and σzz = S₃₃ / J.
                MaterialModel::NeoHookean => -self.mu * self.powers[2].minus_1(J - 1.0) / J,
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
