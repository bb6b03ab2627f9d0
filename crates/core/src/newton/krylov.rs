//! The GMRES correction of a Newton update towards the system's own Jacobian, preconditioned
//! by the factorised symmetric tangent ([`Solver::solve`] once its iterations contract slowly).

use super::saddle::dot;
use super::{Solver, DIFFERENCE_STEP, KRYLOV_DIMENSION, KRYLOV_TOLERANCE};
use crate::terms::{StepContext, Term};

/// Solves the small dense system `a x = b` by Gaussian elimination with partial pivoting; `None`
/// when it is singular.
fn solve_small(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let m = b.len();
    for c in 0..m {
        let p = (c..m).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() <= 1e-300 || !a[p][c].is_finite() {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..m {
            let f = a[r][c] / a[c][c];
            for k in c..m {
                a[r][k] -= f * a[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = vec![0.0; m];
    for r in (0..m).rev() {
        x[r] = (b[r] - (r + 1..m).map(|k| a[r][k] * x[k]).sum::<f64>()) / a[r][r];
    }
    Some(x)
}

impl Solver {
    /// Improves the update `(du, lam)` that the factorised symmetric matrix gave at `u` towards
    /// the solution of the Newton equation with the system's own Jacobian `J`,
    /// `g + J Δu + Cᵀλ = 0`, `C Δu = 0` (`self.g` holds `g` and is kept): GMRES on the correction,
    /// preconditioned by the same factorisation, `J` applied by differences of the gradient.
    /// Returns `None` when GMRES does not reduce the Newton equation's residual by half.
    // the system (terms, context), the point and its update, the factor's frames
    #[allow(clippy::too_many_arguments)]
    pub(super) fn krylov_refine(
        &mut self,
        terms: &[&dyn Term],
        cx: &StepContext,
        u: &[f64],
        (du, lam, current): (&[f64], [f64; 2], [f64; 2]),
        (dphi, turn): (f64, f64),
        length_scale: f64,
    ) -> Option<(Vec<f64>, [f64; 2])> {
        let n = u.len();
        let g0 = self.g.clone();
        let reach = length_scale + u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let apply = |this: &mut Self, x: &[f64], mu: [f64; 2]| -> Option<Vec<f64>> {
            let size = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            if size == 0.0 {
                return Some(
                    (0..n)
                        .map(|i| mu[0] * this.rows[0][i] + mu[1] * this.rows[1][i])
                        .collect(),
                );
            }
            let h = DIFFERENCE_STEP * reach / size;
            let shifted: Vec<f64> = (0..n).map(|i| u[i] + h * x[i]).collect();
            if !this.energy_gradient(terms, &shifted, cx).is_finite() {
                return None;
            }
            Some(
                (0..n)
                    .map(|i| (this.g[i] - g0[i]) / h + mu[0] * this.rows[0][i] + mu[1] * this.rows[1][i])
                    .collect(),
            )
        };
        let result = (|| {
            // the Newton equation's residual at the symmetric update
            let a0 = apply(self, du, lam)?;
            let rho: Vec<f64> = (0..n).map(|i| -g0[i] - a0[i]).collect();
            let beta = dot(&rho, &rho).sqrt();
            // the residual at u with the current multipliers (g alone carries the hinge's reaction)
            let g_norm = (0..n)
                .map(|i| (g0[i] + current[0] * self.rows[0][i] + current[1] * self.rows[1][i]).powi(2))
                .sum::<f64>()
                .sqrt();
            if beta.is_nan() || beta <= KRYLOV_TOLERANCE * g_norm {
                return None;
            }
            let mut v: Vec<Vec<f64>> = vec![rho.iter().map(|x| x / beta).collect()];
            let mut z: Vec<(Vec<f64>, [f64; 2])> = Vec::new();
            let mut hess = [[0.0f64; KRYLOV_DIMENSION]; KRYLOV_DIMENSION + 1];
            let mut best = None;
            for j in 0..KRYLOV_DIMENSION {
                self.rhs[..n].copy_from_slice(&v[j]);
                let (x, mu) = self.saddle_solve(None, dphi, turn);
                let mut w = apply(self, &x, mu)?;
                z.push((x, mu));
                for i in 0..=j {
                    hess[i][j] = dot(&w, &v[i]);
                    for k in 0..n {
                        w[k] -= hess[i][j] * v[i][k];
                    }
                }
                hess[j + 1][j] = dot(&w, &w).sqrt();
                // least squares min ‖β e₁ − H y‖ over the (j+2) × (j+1) Hessenberg matrix, by
                // normal equations (at most 4 × 4)
                let m = j + 1;
                let mut a = vec![vec![0.0; m]; m];
                let mut b = vec![0.0; m];
                for p in 0..m {
                    b[p] = beta * hess[0][p];
                    for q in 0..m {
                        a[p][q] = (0..=m).map(|r| hess[r][p] * hess[r][q]).sum();
                    }
                }
                let y = solve_small(a, b)?;
                let resid: f64 = (0..=m)
                    .map(|r| {
                        let hy: f64 = (0..m).map(|q| hess[r][q] * y[q]).sum();
                        let e = if r == 0 { beta } else { 0.0 };
                        (e - hy).powi(2)
                    })
                    .sum::<f64>()
                    .sqrt();
                best = Some((y, resid));
                if resid <= KRYLOV_TOLERANCE * beta || hess[j + 1][j] <= 1e-14 * beta {
                    break;
                }
                v.push(w.iter().map(|x| x / hess[j + 1][j]).collect());
            }
            let (y, resid) = best?;
            if resid > 0.5 * beta {
                return None;
            }
            let mut out = du.to_vec();
            let mut l = lam;
            for (q, (x, mu)) in z.iter().enumerate().take(y.len()) {
                for i in 0..n {
                    out[i] += y[q] * x[i];
                }
                l[0] += y[q] * mu[0];
                l[1] += y[q] * mu[1];
            }
            Some((out, l))
        })();
        self.g = g0;
        result
    }
}
