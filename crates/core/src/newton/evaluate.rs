//! Evaluations of the terms at a point (energy, gradient, Hessian, into the solver's buffers,
//! with the fixed degrees of freedom imposed) and the measures of the residual: its norm, its
//! bound and the rounding level of the forces in play.

use super::{NewtonSettings, Solver, FORCE_ROUNDING, REFACTOR_CONTRACTION, ROUNDING_FACTOR};
use crate::assembly::Pattern;
use crate::terms::{StepContext, Term};

/// The residual's norm `‖g + Cᵀλ‖∞`, NaN when a component is NaN: `f64::max` drops a NaN, and a
/// residual with one would pass for the largest of its other components, within the bound. No
/// comparison with a bound holds for NaN, so no state with one is taken as converged.
pub(super) fn residual_norm_of(g: &[f64], rows: &[Vec<f64>; 2], lam: [f64; 2]) -> f64 {
    (0..g.len())
        .map(|i| (g[i] + rows[0][i] * lam[0] + rows[1][i] * lam[1]).abs())
        .fold(0.0, |largest, x| match x > largest || x.is_nan() {
            true => x,
            false => largest,
        })
}

impl Solver {
    pub(super) fn energy(terms: &[&dyn Term], u: &[f64], cx: &StepContext) -> f64 {
        terms.iter().map(|term| term.energy(u, cx)).sum()
    }

    pub(super) fn assemble(&mut self, pattern: &Pattern, terms: &[&dyn Term], u: &[f64], cx: &StepContext) -> f64 {
        let start = std::time::Instant::now();
        self.g.iter_mut().for_each(|x| *x = 0.0);
        self.k.iter_mut().for_each(|x| *x = 0.0);
        let mut phi = 0.0;
        for term in terms {
            phi += term.assemble(u, cx, pattern, &mut self.g, &mut self.k);
        }
        self.fixed.apply_vector(&mut self.g);
        self.fixed.apply_matrix(&mut self.k);
        self.timings.assembly += start.elapsed().as_secs_f64();
        phi
    }

    /// The Hessian alone at `u` into `self.k`, where `self.g` already holds the gradient at `u`
    /// (each term's `assemble` adds exactly its `add_hessian` and its `energy_gradient`, so the
    /// gradient is the one a full [`Solver::assemble`] would make, bit for bit).
    pub(super) fn assemble_hessian(&mut self, pattern: &Pattern, terms: &[&dyn Term], u: &[f64], cx: &StepContext) {
        let start = std::time::Instant::now();
        self.k.iter_mut().for_each(|x| *x = 0.0);
        for term in terms {
            term.add_hessian(u, cx, pattern, &mut self.k);
        }
        self.fixed.apply_matrix(&mut self.k);
        self.timings.assembly += start.elapsed().as_secs_f64();
    }

    /// The residual a converged state must reach: `residual_tolerance × load_scale`, but never
    /// below the rounding level of the residual itself, `ROUNDING_FACTOR · ε · max diag K · length_scale`
    /// (internal forces are differences of terms of size `K |x|`; on fine meshes the nodal loads
    /// shrink like `h²` while that level does not).
    pub(super) fn residual_bound(&self, settings: &NewtonSettings) -> f64 {
        let rounding = ROUNDING_FACTOR * f64::EPSILON * self.diagonal_max * settings.length_scale;
        (settings.residual_tolerance * settings.load_scale).max(rounding)
    }

    /// The forces in play at `u` with the multipliers `lambda`: the largest over the degrees of
    /// freedom of `Σ_terms |f_term| + |Cᵀλ|` \[N\], the level at which the residual's rounding
    /// sits ([`FORCE_ROUNDING`]). Leaves `self.g` untouched; costs one gradient pass per term, and
    /// is evaluated only when a step meets the energy criterion but not the residual bound.
    pub(super) fn forces_in_play(&self, terms: &[&dyn Term], u: &[f64], cx: &StepContext, lambda: [f64; 2]) -> f64 {
        let n = self.g.len();
        let mut level: Vec<f64> = (0..n)
            .map(|i| (self.rows[0][i] * lambda[0] + self.rows[1][i] * lambda[1]).abs())
            .collect();
        let mut one = vec![0.0; n];
        for term in terms {
            one.iter_mut().for_each(|x| *x = 0.0);
            term.add_gradient(u, cx, &mut one);
            level.iter_mut().zip(&one).for_each(|(l, f)| *l += f.abs());
        }
        self.fixed.apply_vector(&mut level);
        level.into_iter().fold(0.0, f64::max)
    }

    /// Whether a residual `r` that did not contract below half of `r_prev` is at the rounding of
    /// the forces in play at `u` ([`FORCE_ROUNDING`]).
    pub(super) fn stagnated_at_rounding(
        &self,
        terms: &[&dyn Term],
        u: &[f64],
        cx: &StepContext,
        lambda: [f64; 2],
        r: f64,
        r_prev: f64,
    ) -> bool {
        r > REFACTOR_CONTRACTION * r_prev && r <= FORCE_ROUNDING * self.forces_in_play(terms, u, cx, lambda)
    }

    /// Energy and gradient (no Hessian) at `u` into `self.g`.
    pub(super) fn energy_gradient(&mut self, terms: &[&dyn Term], u: &[f64], cx: &StepContext) -> f64 {
        let start = std::time::Instant::now();
        self.g.iter_mut().for_each(|x| *x = 0.0);
        let mut phi = 0.0;
        for term in terms {
            phi += term.energy_gradient(u, cx, &mut self.g);
        }
        self.fixed.apply_vector(&mut self.g);
        self.timings.residual += start.elapsed().as_secs_f64();
        phi
    }

    /// Gradient only at `u` into `self.g`.
    pub(super) fn gradient_only(&mut self, terms: &[&dyn Term], u: &[f64], cx: &StepContext) {
        let start = std::time::Instant::now();
        self.g.iter_mut().for_each(|x| *x = 0.0);
        for term in terms {
            term.add_gradient(u, cx, &mut self.g);
        }
        self.fixed.apply_vector(&mut self.g);
        self.timings.residual += start.elapsed().as_secs_f64();
    }
}

#[cfg(test)]
mod tests {
    use super::residual_norm_of;

    #[test]
    fn a_nan_component_makes_the_residual_norm_nan_wherever_it_stands() {
        let rows = [vec![0.0; 3], vec![0.0; 3]];
        for g in [[f64::NAN, 1e-9, 0.0], [1e-9, f64::NAN, 0.0], [1e-9, 0.0, f64::NAN]] {
            let r = residual_norm_of(&g, &rows, [0.0; 2]);
            assert!(r.is_nan() && r.partial_cmp(&1.0).is_none(), "{g:?}: norm {r}");
        }
        // the multipliers' part too, and an infinity is the norm
        let rows = [vec![1.0, 0.0, 0.0], vec![0.0; 3]];
        assert!(residual_norm_of(&[0.0; 3], &rows, [f64::NAN, 0.0]).is_nan());
        assert_eq!(
            residual_norm_of(&[-2.0, f64::NEG_INFINITY, 3.0], &rows, [0.0; 2]),
            f64::INFINITY
        );
        assert_eq!(residual_norm_of(&[-2.0, 0.5, 1.0], &rows, [0.0; 2]), 2.0);
    }
}
