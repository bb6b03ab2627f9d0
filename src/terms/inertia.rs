//! Inertia of a Newmark step as an energy: `Π_m(u) = c/2 (u − ũ)ᵀ M (u − ũ)`, `c = 1/(βΔt²)`.
//!
//! `M_{ai,bk} = δ_ik ∫ ρ t N_a N_b dA` is the consistent mass matrix, integrated once with the
//! degree-6 rule (exact for curved P2 elements) and stored in the values layout of the fixed
//! pattern. The step sets the predictor `ũ` and the factor `c` ([`crate::newmark`]).

use super::Term;
use crate::assembly::Pattern;
use crate::fe::for_each_point;
use crate::quadrature::TriangleRule;
use crate::Mesh;

/// Consistent mass matrix (upper triangle in the pattern's layout).
#[derive(Clone, Debug)]
pub struct MassMatrix {
    /// Values, aligned with the pattern.
    pub values: Vec<f64>,
}

impl MassMatrix {
    /// Assembles `∫ ρ t N_a N_b dA` (both components).
    pub fn new(mesh: &Mesh, pattern: &Pattern, rho: f64, thickness: f64) -> Self {
        let mut values = vec![0.0; pattern.nnz()];
        let mut ke = [0.0; 144];
        let rule = TriangleRule::degree6();
        let mut current = usize::MAX;
        let flush = |e: usize, ke: &mut [f64; 144], values: &mut [f64]| {
            pattern.scatter_element(e, ke, values);
            *ke = [0.0; 144];
        };
        for_each_point(mesh, &rule, |e, n, _x, w| {
            if e != current {
                if current != usize::MAX {
                    flush(current, &mut ke, &mut values);
                }
                current = e;
            }
            for a in 0..6 {
                for b in 0..6 {
                    let m = rho * thickness * n[a] * n[b] * w;
                    ke[(2 * a) * 12 + 2 * b] += m;
                    ke[(2 * a + 1) * 12 + 2 * b + 1] += m;
                }
            }
        });
        if current != usize::MAX {
            flush(current, &mut ke, &mut values);
        }
        Self { values }
    }
}

/// The inertia term of one step.
#[derive(Clone, Debug)]
pub struct Inertia<'m> {
    /// The mass matrix.
    pub mass: &'m MassMatrix,
    /// The pattern it lives in.
    pub pattern: &'m Pattern,
    /// `c = 1/(βΔt²)` \[1/s²\].
    pub factor: f64,
    /// Predictor `ũ` \[m\].
    pub predictor: Vec<f64>,
}

impl Inertia<'_> {
    /// The inertia force `c M (u − ũ)` and the energy `½ (u − ũ)·c M (u − ũ)`.
    fn force_and_energy(&self, u: &[f64]) -> (Vec<f64>, f64) {
        let d: Vec<f64> = u.iter().zip(&self.predictor).map(|(a, b)| a - b).collect();
        let mut force = vec![0.0; d.len()];
        self.pattern.sym_matvec(&self.mass.values, &d, &mut force);
        force.iter_mut().for_each(|x| *x *= self.factor);
        let energy = 0.5 * force.iter().zip(&d).map(|(a, b)| a * b).sum::<f64>();
        (force, energy)
    }
}

impl Term for Inertia<'_> {
    fn name(&self) -> &'static str {
        "inertia"
    }

    fn energy(&self, u: &[f64], _t: f64) -> f64 {
        self.force_and_energy(u).1
    }

    fn add_gradient(&self, u: &[f64], t: f64, g: &mut [f64]) {
        self.energy_gradient(u, t, g);
    }

    fn energy_gradient(&self, u: &[f64], _t: f64, g: &mut [f64]) -> f64 {
        let (force, energy) = self.force_and_energy(u);
        g.iter_mut().zip(&force).for_each(|(gi, f)| *gi += f);
        energy
    }

    fn add_hessian(&self, _u: &[f64], _t: f64, _pattern: &Pattern, values: &mut [f64]) {
        values
            .iter_mut()
            .zip(&self.mass.values)
            .for_each(|(k, m)| *k += self.factor * m);
    }

    fn assemble(&self, u: &[f64], t: f64, pattern: &Pattern, g: &mut [f64], values: &mut [f64]) -> f64 {
        self.add_hessian(u, t, pattern, values);
        self.energy_gradient(u, t, g)
    }
}
