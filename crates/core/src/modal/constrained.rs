//! The constrained solve that the shift-invert operator and [`super::constrained_static`] share:
//!
//! ```text
//! [ A  Cᵀ ] [ x ]   [ b ]
//! [ C  0  ] [ μ ] = [ 0 ]          A = K − σM  (positive definite), C: m dense rows,
//! ```
//!
//! solved with one sparse Cholesky factorisation of `A` and the `m × m` Schur complement
//! `S = C A⁻¹ Cᵀ`: `Z = A⁻¹Cᵀ` (m solves, once), `y = A⁻¹ b`, `μ = S⁻¹ C y`, `x = y − Z μ`. Then
//! `C x = C y − S μ = 0` up to rounding, and the multipliers `μ` are the constraint forces of the
//! rows (for the hinge: `−μ` is the force the hinge exerts, [`crate::constraint::Hinge`]).

use faer::{Mat, Side};

use crate::assembly::Pattern;
use crate::error::Error;
use crate::linsolve::Cholesky;

/// `Σ aᵢ bᵢ` over the shorter of the two, summed in eight interleaved partial sums (`i mod 8`)
/// added pairwise at the end: the additions of one sum no longer wait for each other, so the
/// compiler keeps them in vector registers. The set-up's orthogonalisations take thousands of
/// these products of vectors of the mesh's length.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    const LANES: usize = 8;
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; LANES];
    let (ca, cb) = (a.chunks_exact(LANES), b.chunks_exact(LANES));
    let tail: f64 = ca.remainder().iter().zip(cb.remainder()).map(|(x, y)| x * y).sum();
    for (x, y) in ca.zip(cb) {
        for l in 0..LANES {
            acc[l] += x[l] * y[l];
        }
    }
    let [a0, a1, a2, a3, a4, a5, a6, a7] = acc;
    ((a0 + a1) + (a2 + a3)) + ((a4 + a5) + (a6 + a7)) + tail
}

/// A factorised `A` with the constraint rows eliminated through their Schur complement.
pub(crate) struct ConstrainedSolver {
    chol: Cholesky,
    /// The constraint rows `C` (each of length `n`).
    rows: Vec<Vec<f64>>,
    /// `Z = A⁻¹ Cᵀ`, one column per row.
    z: Vec<Vec<f64>>,
    /// Cholesky factor of `S = C Z` (lower triangle, `m × m`).
    s_factor: Mat<f64>,
    /// Cholesky factor of `C Cᵀ` (lower triangle, `m × m`), for [`ConstrainedSolver::project`].
    g_factor: Mat<f64>,
}

/// Solves `L Lᵀ v = b` in place for a lower-triangular `L`.
fn cholesky_solve(l: &Mat<f64>, v: &mut [f64]) {
    let m = v.len();
    for i in 0..m {
        let s: f64 = (0..i).map(|k| l[(i, k)] * v[k]).sum();
        v[i] = (v[i] - s) / l[(i, i)];
    }
    for i in (0..m).rev() {
        let s: f64 = (i + 1..m).map(|k| l[(k, i)] * v[k]).sum();
        v[i] = (v[i] - s) / l[(i, i)];
    }
}

impl ConstrainedSolver {
    /// Factorises `A` (upper-triangle `values` on `pattern`) into `chol` (made by
    /// [`Cholesky::new`] of `pattern` or a [`Cholesky::sibling`] of one) and the Schur complement
    /// of the `rows`; `what` names the matrix in errors (e.g. "K − σM with σ = …").
    pub(crate) fn new(
        mut chol: Cholesky,
        pattern: &Pattern,
        values: &[f64],
        rows: &[Vec<f64>],
        what: &str,
    ) -> Result<Self, Error> {
        let n = pattern.n;
        if values.len() != pattern.nnz() {
            return Err(Error::Modal(format!(
                "{what}: {} matrix values for a pattern of {} entries",
                values.len(),
                pattern.nnz()
            )));
        }
        if let Some((i, r)) = rows.iter().enumerate().find(|(_, r)| r.len() != n) {
            return Err(Error::Modal(format!(
                "constraint row {i} has {} entries, the system has {n} unknowns",
                r.len()
            )));
        }
        if rows.len() >= n {
            return Err(Error::Modal(format!(
                "{} constraint rows for {n} unknowns: nothing is left free",
                rows.len()
            )));
        }
        chol.factor(pattern, values).map_err(|_| {
            Error::Modal(format!(
                "{what} could not be factorised (singular: a zero pivot in L D Lᵀ)"
            ))
        })?;
        // `factor` falls back to L D Lᵀ for an indefinite matrix; the Schur complement and the
        // Lanczos iteration need a positive definite one
        if chol.is_indefinite() {
            return Err(Error::Modal(format!("{what} is not positive definite")));
        }
        // Z = A⁻¹Cᵀ, up to three columns in one pass of the triangular solves over the factor
        let mut z = Vec::with_capacity(rows.len());
        for group in rows.chunks(3) {
            let mut cols: Vec<f64> = group.concat();
            chol.solve_in_place(&mut cols);
            z.extend(cols.chunks_exact(n).map(<[f64]>::to_vec));
        }
        let m = rows.len();
        let s = Mat::<f64>::from_fn(m, m, |i, j| dot(&rows[i], &z[j]));
        let g = Mat::<f64>::from_fn(m, m, |i, j| dot(&rows[i], &rows[j]));
        let g_factor = match g.llt(Side::Lower) {
            Ok(llt) => llt.L().to_owned(),
            Err(_) if m == 0 => Mat::zeros(0, 0),
            Err(_) => {
                return Err(Error::Modal(format!(
                    "the {m} constraint rows are linearly dependent (C Cᵀ is singular)"
                )))
            }
        };
        let s_factor = if m == 0 {
            Mat::zeros(0, 0)
        } else {
            let llt = s.llt(Side::Lower).map_err(|_| {
                Error::Modal(format!(
                    "the {m} constraint rows are linearly dependent (or {what} is not positive definite on \
                     them): their Schur complement C A⁻¹ Cᵀ is not positive definite"
                ))
            })?;
            llt.L().to_owned()
        };
        Ok(Self {
            chol,
            rows: rows.to_vec(),
            z,
            s_factor,
            g_factor,
        })
    }

    /// Solves the saddle-point system for `b` in place (`b` becomes `x`); returns `μ`.
    ///
    /// `x = y − Zμ` meets `C x = 0` up to the rounding of `y = A⁻¹b`, whose components along
    /// the directions `A` barely resists (a free body's rigid motions, `A⁻¹` scaling them by
    /// `1/|σ|m`) may be far larger than `x`; the Euclidean projection onto `ker C` that follows
    /// ([`ConstrainedSolver::project`], a rounding-level change) makes `C x = 0` to the rounding
    /// of `x` itself.
    pub(crate) fn solve_in_place(&mut self, b: &mut [f64]) -> Vec<f64> {
        self.chol.solve_in_place(b);
        // S μ = C y by the Cholesky factor L Lᵀ of S
        let mut mu: Vec<f64> = self.rows.iter().map(|r| dot(r, b)).collect();
        cholesky_solve(&self.s_factor, &mut mu);
        for (zk, &muk) in self.z.iter().zip(&mu) {
            b.iter_mut().zip(zk).for_each(|(x, z)| *x -= z * muk);
        }
        self.project(b);
        mu
    }

    /// `x ← x − Cᵀ (C Cᵀ)⁻¹ C x`: the nearest point of `ker C`.
    pub(crate) fn project(&self, x: &mut [f64]) {
        let mut c: Vec<f64> = self.rows.iter().map(|r| dot(r, x)).collect();
        cholesky_solve(&self.g_factor, &mut c);
        for (row, &ck) in self.rows.iter().zip(&c) {
            x.iter_mut().zip(row).for_each(|(xi, r)| *xi -= r * ck);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::dot;

    #[test]
    fn dot_sums_every_product_for_every_length() {
        // small integers: every partial sum exact, so the eight lanes give the exact value
        for n in 0..40 {
            let a: Vec<f64> = (0..n).map(|i| (i % 7) as f64 - 3.0).collect();
            let b: Vec<f64> = (0..n).map(|i| (i % 5) as f64 + 1.0).collect();
            let exact: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            assert_eq!(dot(&a, &b), exact, "length {n}");
        }
        // the shorter of two lengths
        assert_eq!(dot(&[1.0, 2.0, 3.0], &[1.0, 1.0]), 3.0);
    }
}
