//! Sparse direct solution of the Newton systems.
//!
//! Each Newton iteration solves the saddle-point system of the constrained step
//!
//! ```text
//! [ K  Cᵀ ] [ Δu ]   [ −g ]
//! [ C  0  ] [ λ  ] = [  0 ]
//! ```
//!
//! with `K` the symmetric dynamic stiffness (`M/(βΔt²)` plus the tangent of the terms, positive
//! definite but in a transient buckling of the head, see [`Cholesky::factor`]) and `C` the two
//! hinge rows. We factorise `K = LLᵀ` (faer's sparse Cholesky; `L D Lᵀ` where `K` is indefinite) and eliminate
//! the two multipliers through the 2×2 Schur complement `S = C K⁻¹ Cᵀ`:
//! `y = −K⁻¹g`, `Z = K⁻¹Cᵀ`, `λ = S⁻¹ C y`, `Δu = y − Z λ`. This keeps the factorised matrix
//! positive definite (an LDLᵀ of the saddle-point matrix needs the multipliers ordered last, or a
//! zero pivot appears), and it is exact.
//!
//! The fill-reducing ordering (AMD) and the symbolic factorisation are computed once per run from
//! the fixed pattern ([`crate::assembly::Pattern`]); every Newton iteration only refactorises
//! numerically into preallocated storage.
//!
//! A simplicial factor's triangular solves run in two halves of its elimination tree side by side
//! (`linsolve/split.rs`): a solve streams the factor from memory, and with the split each of two
//! cores streams 55 % of the tutorial's factor instead of one core all of it. The sums into the
//! common ancestors' rows come in another order than in the sequential solve (1e-13 rad in θ over
//! the tutorial's swing); the result does not depend on the number of threads. The
//! `L D Lᵀ` of an indefinite matrix and a supernodal factor (large meshes, the deformable wall's
//! system) are solved by faer.
//!
//! The factor's indices are 32-bit: a triangular solve streams the factor's values and row
//! indices once each, and 4-byte indices make that a quarter less memory to read than 8-byte ones
//! (the tutorial's factor has 162 thousand entries, 2.6 MB with 8-byte indices, more than a core's
//! cache). The arithmetic and the ordering are the same, so are the results, bit for bit.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LdltRef, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use crate::assembly::Pattern;
use crate::error::Error;

mod split;
use split::{Buffers, TreeSplit};

/// A Cholesky factorisation with a fixed symbolic structure (`L Lᵀ`, or `L D Lᵀ` for an
/// indefinite matrix, see [`Cholesky::factor`]).
pub struct Cholesky {
    /// The symbolic analysis, shared with the [`Cholesky::sibling`]s.
    symbolic: Arc<SymbolicCholesky<u32>>,
    /// The split of a simplicial factor's tree for the solves (`split.rs`), shared likewise.
    split: Option<Arc<TreeSplit>>,
    /// The split solve's work vectors.
    buffers: Buffers,
    /// The pattern's column pointers and row indices, 32-bit.
    col_ptr: Arc<[u32]>,
    row_idx: Arc<[u32]>,
    l_values: Vec<f64>,
    mem: MemBuffer,
    par: Par,
    factored: bool,
    /// Whether the factorisation is `L D Lᵀ` (an indefinite matrix), not `L Lᵀ`.
    indefinite: bool,
}

/// The matrix could not be factorised: not positive definite, and a zero pivot in `L D Lᵀ`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Singular;

/// Right-hand sides solved together at most.
const MAX_RHS: usize = 3;

impl Cholesky {
    /// Symbolic analysis (ordering, elimination tree, supernodes) of `pattern`.
    pub fn new(pattern: &Pattern) -> Result<Self, Error> {
        let narrow = |v: &[usize], what: &str| -> Result<Arc<[u32]>, Error> {
            v.iter()
                .map(|&i| u32::try_from(i))
                .collect::<Result<_, _>>()
                .map_err(|_| Error::LinearSolver(format!("the system's {what} exceed 32-bit indices")))
        };
        let col_ptr = narrow(&pattern.col_ptr, "entries")?;
        let row_idx = narrow(&pattern.row_idx, "unknowns")?;
        let sym = symbolic_ref(pattern.n, &col_ptr, &row_idx);
        let symbolic = factorize_symbolic_cholesky(
            sym,
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| Error::LinearSolver(format!("symbolic Cholesky analysis failed: {e:?}")))?;
        // Two threads pay off only for large supernodal factorisations.
        let par = if pattern.n > 40_000 { Par::rayon(0) } else { Par::Seq };
        let split = match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(l) => {
                TreeSplit::new(l.col_ptr(), l.row_idx(), symbolic.perm().map(|p| p.arrays().0)).map(Arc::new)
            }
            SymbolicCholeskyRaw::Supernodal(_) => None,
        };
        Self::with_analysis(Arc::new(symbolic), split, col_ptr, row_idx, par)
    }

    /// A factorisation of another matrix on the same pattern: this one's symbolic analysis (the
    /// ordering and the structure of `L`, shared, not recomputed), its own numeric storage, nothing
    /// factorised yet.
    pub fn sibling(&self) -> Result<Self, Error> {
        Self::with_analysis(
            Arc::clone(&self.symbolic),
            self.split.clone(),
            Arc::clone(&self.col_ptr),
            Arc::clone(&self.row_idx),
            self.par,
        )
    }

    fn with_analysis(
        symbolic: Arc<SymbolicCholesky<u32>>,
        split: Option<Arc<TreeSplit>>,
        col_ptr: Arc<[u32]>,
        row_idx: Arc<[u32]>,
        par: Par,
    ) -> Result<Self, Error> {
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
            symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(MAX_RHS, par),
        ]);
        let mem =
            MemBuffer::try_new(req).map_err(|_| Error::LinearSolver("out of memory for the factorisation".into()))?;
        let l_values = vec![0.0; symbolic.len_val()];
        let buffers = split.as_ref().map(|s| s.buffers()).unwrap_or_default();
        Ok(Self {
            symbolic,
            split,
            buffers,
            col_ptr,
            row_idx,
            l_values,
            mem,
            par,
            factored: false,
            indefinite: false,
        })
    }

    /// Whether the last successful factorisation was `L D Lᵀ` (the matrix is not positive
    /// definite), not `L Lᵀ`.
    pub fn is_indefinite(&self) -> bool {
        self.indefinite
    }

    /// Number of stored entries of the factor `L`.
    pub fn factor_nnz(&self) -> usize {
        self.l_values.len()
    }

    /// Numeric factorisation of the matrix with upper-triangle `values` in `pattern`: `L Lᵀ`, or
    /// where that fails (the matrix is not positive definite) `L D Lᵀ` in the same ordering and
    /// structure, without pivoting, which fails only at a zero pivot.
    ///
    /// Why an indefinite Newton matrix is solved rather than refused: after a blow a ring-shaped
    /// head compressed by the contact and its own ringing has modes whose geometric stiffness is
    /// negative and larger than the inertia `M/(βΔt²)` of a step of milliseconds (a transient
    /// dynamic buckling that the physics goes through). The step's equations still have their
    /// solution; only the Cholesky factorisation of their Jacobian fails. Refusing it would halve
    /// the step until the inertia dominates: seed 24's case 18 of the robustness campaign (an
    /// 821 MPa ring against the deformable wall) took 11 such cut-backs in its first 0.2 s, and
    /// takes none with `L D Lᵀ`. A positive definite matrix takes `L Lᵀ`, and its result does not
    /// depend on the fallback.
    pub fn factor(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), Singular> {
        debug_assert_eq!(pattern.nnz(), self.row_idx.len(), "the pattern of Cholesky::new");
        let a = SparseColMatRef::new(symbolic_ref(pattern.n, &self.col_ptr, &self.row_idx), values);
        self.factored = false;
        let stack = MemStack::new(&mut self.mem);
        let positive = self
            .symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                a,
                Side::Upper,
                Default::default(),
                self.par,
                stack,
                Default::default(),
            )
            .is_ok();
        self.indefinite = !positive;
        if !positive {
            let stack = MemStack::new(&mut self.mem);
            self.symbolic
                .factorize_numeric_ldlt(
                    &mut self.l_values,
                    a,
                    Side::Upper,
                    Default::default(),
                    self.par,
                    stack,
                    Default::default(),
                )
                .map_err(|_| Singular)?;
        }
        self.factored = true;
        Ok(())
    }

    /// Solves `K X = B` in place for up to three right-hand sides stored column after column in `b`.
    ///
    /// # Panics
    /// If no factorisation succeeded before, or `b` is not a multiple of the dimension.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        assert!(self.factored, "solve before a successful factorisation");
        let n = self.symbolic.nrows();
        let k = b.len() / n;
        assert!(k * n == b.len() && k <= MAX_RHS);
        if let (Some(split), false) = (&self.split, self.indefinite) {
            for column in b.chunks_exact_mut(n) {
                split.solve(&self.l_values, column, &mut self.buffers);
            }
            return;
        }
        let rhs = MatMut::from_column_major_slice_mut(b, n, k);
        if self.indefinite {
            let ldlt = LdltRef::new(&self.symbolic, &self.l_values);
            ldlt.solve_in_place_with_conj(Conj::No, rhs, self.par, MemStack::new(&mut self.mem));
            return;
        }
        let llt = LltRef::new(&self.symbolic, &self.l_values);
        llt.solve_in_place_with_conj(Conj::No, rhs, self.par, MemStack::new(&mut self.mem));
    }
}

fn symbolic_ref<'a>(n: usize, col_ptr: &'a [u32], row_idx: &'a [u32]) -> SymbolicSparseColMatRef<'a, u32> {
    SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The solve in two halves of the elimination tree (`split.rs`) is the plain sequential solve
    /// up to the order of the sums into the top's rows: on the tutorial's pattern (and one refined
    /// twice) with a diagonally dominant matrix, the two solutions agree to 1e-13 of the largest
    /// entry (rounding of a different summation order, condition number of order 10), and the
    /// split one satisfies `K x = b` to 1e-12 of `b`.
    #[test]
    fn the_split_solve_is_the_plain_one() {
        for refine in [1.0, 2.0] {
            let mut cfg = crate::config::Config::default();
            cfg.mesh.refine = refine;
            let mesh = crate::mesh::generate_with_stats(&cfg).expect("mesh").0;
            let pattern = Pattern::new(&mesh, &[]);
            let n = pattern.n;
            let mut values = vec![0.0; pattern.nnz()];
            let mut diagonal = vec![1.0; n];
            for c in 0..n {
                for k in pattern.col_ptr[c]..pattern.col_ptr[c + 1] {
                    let r = pattern.row_idx[k];
                    if r != c {
                        values[k] = -(1.0 + ((7 * r + 13 * c) % 5) as f64 / 5.0);
                        diagonal[r] -= values[k];
                        diagonal[c] -= values[k];
                    }
                }
            }
            for c in 0..n {
                let k = pattern.position(c, c).expect("a diagonal entry");
                values[k] = diagonal[c];
            }
            let mut split = Cholesky::new(&pattern).expect("analysis");
            assert!(split.split.is_some(), "the pendulum's tree splits (refine = {refine})");
            let mut plain = split.sibling().expect("sibling");
            plain.split = None;
            split.factor(&pattern, &values).expect("positive definite");
            plain.factor(&pattern, &values).expect("positive definite");
            let b: Vec<f64> = (0..2 * n).map(|i| ((i * 37) % 101) as f64 - 50.0).collect();
            let (mut x, mut y) = (b.clone(), b.clone());
            split.solve_in_place(&mut x);
            plain.solve_in_place(&mut y);
            let largest = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let difference = x.iter().zip(&y).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                difference <= 1e-13 * largest,
                "difference {difference:e} of {largest:e}"
            );
            for (x, b) in x.chunks_exact(n).zip(b.chunks_exact(n)) {
                let mut kx = vec![0.0; n];
                pattern.sym_matvec(&values, x, &mut kx);
                let residual = kx.iter().zip(b).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(residual <= 1e-12 * 50.0, "residual {residual:e}");
            }
        }
    }
}
