//! The law at several points at once, and the power series it rests on.
//!
//! The Neo-Hookean law evaluates `(1 + x)^a − 1` at every quadrature point, for `|x| < 10⁻³` (every
//! point of a steel pendulum) by the binomial series of [`Power`]. The series is six dependent
//! steps, a chain the processor cannot shorten; the kernels therefore take an element's points
//! side by side ([`Power::series_lanes`]), whose independent chains overlap. Each batched function
//! here computes exactly what its one-point counterpart in [`super`] does, operation for operation,
//! so the numbers are the same bit for bit; where a point leaves the series' range they fall back
//! to the one-point functions.

use super::{cofactor, det, invariants, sym_dot, Material, Sym, VecF, TAYLOR_LIMIT};
use crate::config::MaterialModel;

/// `(1 + x)^a − 1` for a fixed exponent `a` ([`super::pow1p_minus_1`]) with the series' coefficients
/// `(a − j)/(j + 1)` computed once: a material evaluates its two powers at every quadrature
/// point of every evaluation (three powers), and the coefficients (and `k = λ/μ`, a division) are the same each
/// time. The same numbers, bit for bit, as computing them in place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Power {
    a: f64,
    /// `(a − 1)/2, (a − 2)/3, (a − 3)/4, (a − 4)/5, (a − 5)/6`.
    c: [f64; 5],
}

impl Power {
    /// The power `a`.
    pub fn new(a: f64) -> Self {
        Self {
            a,
            c: [
                (a - 1.0) * 0.5,
                (a - 2.0) * (1.0 / 3.0),
                (a - 3.0) * 0.25,
                (a - 4.0) * 0.2,
                (a - 5.0) * (1.0 / 6.0),
            ],
        }
    }

    /// [`Power::minus_1`] of `L` values, each `|x| < 10⁻³` (the series), side by side: the series'
    /// six dependent steps are the cost of one value, and `L` independent chains overlap in the
    /// processor. The same numbers bit for bit.
    #[inline]
    fn series_lanes<const L: usize>(&self, x: &[f64; L]) -> [f64; L] {
        let c = &self.c;
        let mut t = [0.0; L];
        for i in 0..L {
            t[i] = 1.0 + c[4] * x[i];
        }
        for c in [c[3], c[2], c[1], c[0]] {
            for i in 0..L {
                t[i] = 1.0 + c * x[i] * t[i];
            }
        }
        std::array::from_fn(|i| self.a * x[i] * t[i])
    }

    /// `(1 + x)^a − 1`.
    #[inline]
    pub fn minus_1(&self, x: f64) -> f64 {
        if x.abs() < 1e-3 {
            // a x (1 + (a−1)/2 x (1 + (a−2)/3 x (1 + … (1 + (a−5)/6 x))))
            let c = &self.c;
            let t = 1.0 + c[4] * x;
            let t = 1.0 + c[3] * x * t;
            let t = 1.0 + c[2] * x * t;
            let t = 1.0 + c[1] * x * t;
            let t = 1.0 + c[0] * x * t;
            self.a * x * t
        } else {
            (self.a * x.ln_1p()).exp_m1()
        }
    }
}

impl Material {
    /// [`Material::strain_energy`] of `L` strains, the same numbers bit for bit. For the
    /// Neo-Hookean law with every `|det C − 1| < 10⁻³` (every point of a steel pendulum) the
    /// strains go through the power series side by side: its six dependent steps are the cost of
    /// one strain, and `L` independent chains overlap in the processor; otherwise one by one.
    pub fn strain_energies<const L: usize>(&self, e: &[Sym; L]) -> [(f64, f64); L] {
        if self.model == MaterialModel::NeoHookean {
            let (mut tr, mut x) = ([0.0; L], [0.0; L]);
            for i in 0..L {
                (tr[i], x[i]) = invariants(&e[i]);
            }
            if x.iter().all(|x| x.abs() < 1e-3) {
                let power = self.powers[0].series_lanes(&x);
                let mut out = [(0.0, 0.0); L];
                for i in 0..L {
                    let second = self.mu_over_k * power[i];
                    out[i] = (self.mu * tr[i] + second, (self.mu * tr[i]).abs() + second.abs());
                }
                return out;
            }
        }
        std::array::from_fn(|i| self.strain_energy(&e[i]))
    }

    /// [`Material::discrete_stress`] at `L` points, the same numbers bit for bit. For the
    /// Neo-Hookean law with every point's mid-step `|det C − 1| < 10⁻³` and strain increment
    /// `0 < |D| < 10⁻⁴` (every point of a steel pendulum in a step without an impact) the points go
    /// through the series and the Taylor term side by side, as in
    /// [`Material::strain_energies`]; otherwise one by one.
    pub fn discrete_stresses<const L: usize>(&self, e0: &[Sym; L], psi0: &[(f64, f64); L], e1: &[Sym; L]) -> [Sym; L] {
        let one_by_one = || std::array::from_fn(|i| self.discrete_stress(&e0[i], psi0[i], &e1[i]));
        if self.model != MaterialModel::NeoHookean {
            return one_by_one();
        }
        let (mut em, mut de) = ([[0.0; 3]; L], [[0.0; 3]; L]);
        let (mut x, mut norm2) = ([0.0; L], [0.0; L]);
        for i in 0..L {
            em[i] = [
                0.5 * (e0[i][0] + e1[i][0]),
                0.5 * (e0[i][1] + e1[i][1]),
                0.5 * (e0[i][2] + e1[i][2]),
            ];
            de[i] = [e1[i][0] - e0[i][0], e1[i][1] - e0[i][1], e1[i][2] - e0[i][2]];
            x[i] = invariants(&em[i]).1;
            norm2[i] = sym_dot(&de[i], &de[i]);
        }
        let series = (0..L).all(|i| x[i].abs() < 1e-3 && norm2[i] > 0.0 && norm2[i] < TAYLOR_LIMIT * TAYLOR_LIMIT);
        if !series {
            return one_by_one();
        }
        // second_piola_parts at E_m, its power by the series
        let power = self.powers[1].series_lanes(&x);
        let mu = self.mu;
        let mut out = [[0.0; 3]; L];
        for i in 0..L {
            let d_minus_1 = power[i];
            let d = 1.0 + d_minus_1;
            let (em, de) = (&em[i], &de[i]);
            let mut s = [
                mu * (-d_minus_1 - 2.0 * d * em[1]),
                mu * (-d_minus_1 - 2.0 * d * em[0]),
                2.0 * mu * d * em[2],
            ];
            // the Taylor term of discrete_stress
            let c = self.taylor_term(em, de, d, 1.0 / (1.0 + x[i])) / norm2[i];
            for j in 0..3 {
                s[j] += c * de[j];
            }
            out[i] = s;
        }
        out
    }

    /// [`Material::first_piola_stress`] at `L` admissible points, the same numbers bit for bit: for
    /// the Neo-Hookean law with every `|J − 1| < 10⁻³` the points go through the series of `J^(−k)`
    /// side by side (as in [`Material::strain_energies`]); otherwise one by one.
    #[allow(non_snake_case)]
    pub fn first_piola_stresses<const L: usize>(&self, F: &[VecF; L]) -> [[f64; 4]; L] {
        let one_by_one = || std::array::from_fn(|i| self.first_piola_stress(&F[i]));
        if self.model != MaterialModel::NeoHookean {
            return one_by_one();
        }
        let mut x = [0.0; L];
        for i in 0..L {
            x[i] = det(&F[i]) - 1.0;
        }
        if !x.iter().all(|x| x.abs() < 1e-3) {
            return one_by_one();
        }
        let power = self.powers[2].series_lanes(&x);
        let mut out = [[0.0; 4]; L];
        for i in 0..L {
            // first_piola_of: μ (F − J^(−k−1) cof F)
            let J = det(&F[i]);
            let jk1 = (1.0 + power[i]) / J;
            let c = cofactor(&F[i]);
            out[i] = [0, 1, 2, 3].map(|v| self.mu * (F[i][v] - jk1 * c[v]));
        }
        out
    }
}
