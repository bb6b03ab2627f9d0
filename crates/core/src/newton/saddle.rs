//! The linear solve of an iteration: the saddle-point system of the tangent and the hinge with
//! the current factorisation, rotated from its frame into the current one.

use super::Solver;

/// Rotates every `(x, y)` pair of `v` by `angle`.
fn rotate_pairs(v: &mut [f64], angle: f64) {
    let (s, c) = angle.sin_cos();
    for p in v.chunks_exact_mut(2) {
        let (x, y) = (p[0], p[1]);
        p[0] = c * x - s * y;
        p[1] = s * x + c * y;
    }
}

pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Solver {
    /// `rows[k] · v`, summed over the rows' support in ascending order: the same number as the
    /// product over every unknown (whose other terms are exact zeros), at the cost of the hinge
    /// edge's few dozen unknowns instead of all.
    pub(super) fn row_dot(&self, k: usize, v: &[f64]) -> f64 {
        let row = &self.rows[k];
        self.row_support.iter().map(|&i| row[i] * v[i]).sum()
    }

    /// Solves `K̃ Δu + Cᵀλ = −g`, `C(u + Δu) = 0` with the current factorisation, rotated by `dphi`
    /// from its frame into the current one; returns `(Δu, λ, δ²)`.
    pub(super) fn constrained_solve(&mut self, u: &[f64], dphi: f64, turn: f64) -> (Vec<f64>, [f64; 2], f64) {
        let start = std::time::Instant::now();
        let n = self.g.len();
        for i in 0..n {
            self.rhs[i] = -self.g[i];
        }
        let (du, lam) = self.saddle_solve(Some(u), dphi, turn);
        let decrement = -(dot(&du, &self.g) + lam[0] * self.row_dot(0, &du) + lam[1] * self.row_dot(1, &du));
        self.timings.solve += start.elapsed().as_secs_f64();
        (du, lam, decrement)
    }

    /// Solves the saddle-point system with the factorised matrix for the right-hand side in
    /// `self.rhs[..n]`: `K̃ x + Cᵀμ = rhs` with `C (u + x) = 0` (`C x = 0` without `u`), the
    /// matrix in its frame turned by `dphi` and the right-hand side by `turn`.
    pub(super) fn saddle_solve(&mut self, u: Option<&[f64]>, dphi: f64, turn: f64) -> (Vec<f64>, [f64; 2]) {
        let n = self.g.len();
        // the right-hand side turned by `turn`, rotated by −dphi into the factor's frame, solved,
        // rotated back.
        let y = &mut self.rhs[..n];
        let rot = self.rotating;
        if turn - dphi != 0.0 {
            rotate_pairs(&mut y[..rot], turn - dphi);
        }
        self.chol.as_mut().expect("a factorisation exists").solve_in_place(y);
        if dphi != 0.0 {
            rotate_pairs(&mut y[..rot], dphi);
        }
        // The hinge columns K⁻¹Cᵀ in the current frame: Q(dphi) K_f⁻¹ Q(−dphi) Cᵀ. A rotation of
        // the two columns of Cᵀ (each node's weight times e_x, e_y) mixes them:
        // Q(β) c_x = cos β c_x + sin β c_y, Q(β) c_y = −sin β c_x + cos β c_y, β = −dphi.
        let (sb, cb) = (-dphi).sin_cos();
        let (fx, fy) = self.hinge_columns.split_at(n);
        let (zx, zy) = self.rhs[n..].split_at_mut(n);
        for i in 0..n {
            zx[i] = cb * fx[i] + sb * fy[i];
            zy[i] = -sb * fx[i] + cb * fy[i];
        }
        if dphi != 0.0 {
            rotate_pairs(&mut zx[..rot], dphi);
            rotate_pairs(&mut zy[..rot], dphi);
        }
        let (y, z) = self.rhs.split_at(n);
        let (zx, zy) = z.split_at(n);
        let s = [
            [self.row_dot(0, zx), self.row_dot(0, zy)],
            [self.row_dot(1, zx), self.row_dot(1, zy)],
        ];
        // C(u + Δu) = 0 with Δu = y − Zλ  ⇒  S λ = C y + C u.
        let b = match u {
            Some(u) => [
                self.row_dot(0, y) + self.row_dot(0, u),
                self.row_dot(1, y) + self.row_dot(1, u),
            ],
            None => [self.row_dot(0, y), self.row_dot(1, y)],
        };
        let det = s[0][0] * s[1][1] - s[0][1] * s[1][0];
        let lam = [
            (b[0] * s[1][1] - b[1] * s[0][1]) / det,
            (s[0][0] * b[1] - s[1][0] * b[0]) / det,
        ];
        let du: Vec<f64> = (0..n).map(|i| y[i] - zx[i] * lam[0] - zy[i] * lam[1]).collect();
        // the turned system carries the turned multipliers: Q(turn) Cᵀλ = Cᵀ R(turn) λ
        let lam = if turn != 0.0 {
            let (s, c) = (-turn).sin_cos();
            [c * lam[0] - s * lam[1], s * lam[0] + c * lam[1]]
        } else {
            lam
        };
        (du, lam)
    }
}
