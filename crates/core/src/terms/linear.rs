//! Loads linear in the displacement, `Π(u) = E₀ + f·u` with a constant `f = ∂Π/∂u`: gravity, the
//! d'Alembert forces of the initial rigid motion, the `−α ∇Π(uₙ)` term of HHT-α.
//!
//! **Gravity** along −y: `Π_g(u) = ∫_Ω₀ ρ t g (Y + u_y) dA`, the potential energy relative to the
//! pivot height (`y = 0`): `f_a = ρ t g ∫ N_a dA` on the `y` components and `E₀ = ρ t g ∫ Y dA`,
//! both integrated once with the degree-6 rule (exact on curved P2 elements).

use super::{StepContext, StepStart, Term};
use crate::assembly::Pattern;
use crate::fe::for_each_point;
use crate::mesh::Mesh;
use crate::quadrature::TriangleRule;

/// A load linear in the displacement (see the module doc).
#[derive(Clone, Debug)]
pub struct Linear {
    /// `f = ∂Π/∂u` (constant) \[N\].
    pub load_gradient: Vec<f64>,
    /// `Π(0)` \[J\].
    pub reference_energy: f64,
}

/// Uniform gravity on a body: a linear load ([`Linear::gravity`]).
pub type Gravity = Linear;

impl Linear {
    /// The load `Π = f·u` of the nodal forces `f`.
    pub fn new(load_gradient: Vec<f64>) -> Self {
        Self {
            load_gradient,
            reference_energy: 0.0,
        }
    }

    /// Gravity of magnitude `g` \[m/s²\] on a body of density `rho` and thickness `thickness`.
    pub fn gravity(mesh: &Mesh, rho: f64, thickness: f64, g: f64) -> Self {
        let mut load_gradient = crate::assembly::written_zeros(2 * mesh.num_nodes());
        let mut reference_energy = 0.0;
        let c = rho * thickness * g;
        for_each_point(mesh, &TriangleRule::degree6(), |e, n, x, w| {
            reference_energy += c * x[1] * w;
            for (a, &node) in mesh.triangles[e].iter().enumerate() {
                load_gradient[2 * node + 1] += c * n[a] * w;
            }
        });
        Self {
            load_gradient,
            reference_energy,
        }
    }
}

impl Term for Linear {
    fn name(&self) -> &'static str {
        "linear load"
    }

    fn energy(&self, u: &[f64], _cx: &StepContext) -> f64 {
        self.reference_energy + self.load_gradient.iter().zip(u).map(|(w, x)| w * x).sum::<f64>()
    }

    fn add_gradient(&self, _u: &[f64], _cx: &StepContext, g: &mut [f64]) {
        g.iter_mut().zip(&self.load_gradient).for_each(|(gi, w)| *gi += w);
    }

    fn add_hessian(&self, _u: &[f64], _cx: &StepContext, _pattern: &Pattern, _values: &mut [f64]) {}

    /// Linear in `u`: the discrete gradient is the gradient (exact energy change, and the moment of
    /// the load at the mid-step positions is the exact mid-step value).
    fn add_discrete_gradient(
        &self,
        _start: &StepStart,
        u1: &[f64],
        cx: &StepContext,
        factor: f64,
        g: &mut [f64],
    ) -> f64 {
        g.iter_mut()
            .zip(&self.load_gradient)
            .for_each(|(gi, w)| *gi += factor * w);
        self.energy(u1, cx)
    }
}
