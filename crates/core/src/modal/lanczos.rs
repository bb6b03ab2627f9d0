//! Shift-invert Lanczos with full reorthogonalisation in the `M` inner product.
//!
//! For `K φ = λ M φ`, `C φ = 0` and a shift `σ` with `A = K − σM` positive definite on the
//! problem's space, the operator
//!
//! ```text
//! W x = G M x,     G b = the x of  A x + Cᵀμ = b, C x = 0        ([`ConstrainedSolver`])
//! ```
//!
//! maps into `ker C`, is self-adjoint in `⟨x, y⟩_M = yᵀ M x` there, and has the eigenpairs
//! `W φ = θ φ`, `θ = 1/(λ − σ)`: the eigenvalues nearest `σ` become the largest `θ`, which the
//! Lanczos iteration finds first. With `q₁ = W r / ‖W r‖_M` (`r` a fixed pseudo-random vector),
//!
//! ```text
//! w = W q_j,  α_j = ⟨w, q_j⟩_M,  w ← w − α_j q_j − β_{j−1} q_{j−1},
//! w ← w − Σ_{i ≤ j} ⟨w, q_i⟩_M q_i   (full reorthogonalisation, repeated while a pass
//!                                     shortens w by more than a factor 1/√2),
//! β_j = ‖w‖_M,  q_{j+1} = w / β_j,
//! ```
//!
//! `W Q_j = Q_j T_j + β_j q_{j+1} e_jᵀ` with `T_j` tridiagonal. A Ritz pair `(θ, Q_j s)` of
//! `T_j s = θ s` has the residual `‖W y − θ y‖_M = β_j |s_j|`; the `n` largest Ritz values have
//! converged when this is below `tol · θ`, checked after every step from the `n`-th on. The Ritz vectors are `M`-orthonormal because the
//! Lanczos vectors are, and `λ = σ + 1/θ`.

use faer::{Mat, Side};

use super::constrained::{dot, ConstrainedSolver};
use crate::error::Error;
use crate::terms::inertia::MassMatrix;

/// Relative Ritz residual `β_j |s_j| / θ` at which a pair counts as converged.
pub(crate) const RITZ_TOLERANCE: f64 = 1e-11;

/// The converged Ritz pairs: `θ` descending and the vectors.
pub(crate) struct RitzPairs {
    pub theta: Vec<f64>,
    pub vectors: Vec<Vec<f64>>,
}

/// A reproducible start vector (a linear congruential sequence in `[−1, 1)`).
fn start_vector(n: usize) -> Vec<f64> {
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    (0..n)
        .map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

/// The `wanted` largest eigenpairs of `W = G M` (see the module doc); at most `max_steps` steps
/// (the dimension of `ker C` caps it too).
pub(crate) fn largest(
    solver: &mut ConstrainedSolver,
    mass: &MassMatrix,
    n: usize,
    free: usize,
    wanted: usize,
    max_steps: usize,
) -> Result<RitzPairs, Error> {
    let max_steps = max_steps.min(free).max(wanted);
    let mut q: Vec<Vec<f64>> = Vec::with_capacity(max_steps + 1);
    let mut mq: Vec<Vec<f64>> = Vec::with_capacity(max_steps + 1);
    let (mut alpha, mut beta) = (Vec::<f64>::new(), Vec::<f64>::new());
    let mut w = vec![0.0; n];
    let mut mw = vec![0.0; n];
    // q₁ = W r normalised: in ker C and in the range of the operator
    let r = start_vector(n);
    mass.apply(&r, &mut w);
    solver.solve_in_place(&mut w);
    mass.apply(&w, &mut mw);
    let norm = dot(&w, &mw).sqrt();
    if norm.is_nan() || norm <= 0.0 {
        return Err(Error::Modal(
            "the shift-invert operator maps the start vector to zero or NaN (is the mass matrix zero?)".into(),
        ));
    }
    q.push(w.iter().map(|x| x / norm).collect());
    mq.push(mw.iter().map(|x| x / norm).collect());
    loop {
        let j = q.len() - 1;
        // w = W q_j = G (M q_j)
        w.copy_from_slice(&mq[j]);
        solver.solve_in_place(&mut w);
        let a = dot(&w, &mq[j]);
        if !a.is_finite() {
            return Err(Error::Modal(format!("non-finite value in Lanczos step {}", j + 1)));
        }
        alpha.push(a);
        // the three-term recurrence, then the full reorthogonalisation by classical Gram–Schmidt
        // against every q_i, repeated only while a pass removes more than 30 % of the length
        // (the Daniel–Gragg–Kaufman–Stewart criterion): the recurrence has taken the large
        // components, so one pass is usually enough, and each pass reads every earlier vector
        w.iter_mut().zip(&q[j]).for_each(|(x, y)| *x -= a * y);
        if let (Some(&b), Some(prev)) = (beta.last(), j.checked_sub(1).map(|i| &q[i])) {
            w.iter_mut().zip(prev).for_each(|(x, y)| *x -= b * y);
        }
        mass.apply(&w, &mut mw);
        let mut b = dot(&w, &mw).max(0.0).sqrt();
        for _ in 0..3 {
            let coef: Vec<f64> = mq.iter().map(|m| dot(&w, m)).collect();
            for (qi, c) in q.iter().zip(&coef) {
                w.iter_mut().zip(qi).for_each(|(x, y)| *x -= c * y);
            }
            mass.apply(&w, &mut mw);
            let after = dot(&w, &mw).max(0.0).sqrt();
            let enough = after >= std::f64::consts::FRAC_1_SQRT_2 * b;
            b = after;
            if enough {
                break;
            }
        }
        let steps = j + 1;
        let exhausted = steps >= max_steps || b <= 1e-14 * a.abs();
        // every step from the wanted count on: a step costs a sparse solve, the check an
        // eigen-decomposition of a matrix of at most a few dozen rows, so the iteration stops at
        // the first step that has the wanted pairs (24 steps for 8 modes on the tutorial's mesh)
        if steps >= wanted {
            if let Some(pairs) = ritz(&alpha, &beta, b, &q, wanted)? {
                return Ok(pairs);
            }
        }
        if exhausted {
            let message = if steps >= max_steps {
                format!("Lanczos did not converge in {steps} steps for {wanted} eigenpairs; try a shift closer to the wanted eigenvalues or fewer modes")
            } else {
                format!("the Krylov space is exhausted after {steps} steps, short of {wanted} converged eigenpairs (the constrained problem has fewer free directions than modes asked?)")
            };
            return Err(Error::Modal(message));
        }
        beta.push(b);
        q.push(w.iter().map(|x| x / b).collect());
        mq.push(mw.iter().map(|x| x / b).collect());
    }
}

/// The `wanted` largest Ritz pairs of `T_j`, if they have all converged.
fn ritz(alpha: &[f64], beta: &[f64], b_next: f64, q: &[Vec<f64>], wanted: usize) -> Result<Option<RitzPairs>, Error> {
    let k = alpha.len();
    let t = Mat::<f64>::from_fn(k, k, |r, c| {
        if r == c {
            alpha[r]
        } else if r == c + 1 {
            beta[c]
        } else if c == r + 1 {
            beta[r]
        } else {
            0.0
        }
    });
    let evd = t
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| Error::Modal(format!("eigenvalues of the {k}×{k} Lanczos matrix: {e:?}")))?;
    let (s, u) = (evd.S().column_vector(), evd.U());
    // ascending: the largest θ are the last
    let order: Vec<usize> = (0..k).rev().take(wanted).collect();
    let converged = order
        .iter()
        .all(|&i| s[i] > 0.0 && b_next * u[(k - 1, i)].abs() <= RITZ_TOLERANCE * s[i]);
    if !converged {
        return Ok(None);
    }
    let n = q[0].len();
    let mut vectors = Vec::with_capacity(wanted);
    for &i in &order {
        let mut y = vec![0.0; n];
        for (l, ql) in q.iter().take(k).enumerate() {
            let c = u[(l, i)];
            y.iter_mut().zip(ql).for_each(|(a, b)| *a += c * b);
        }
        vectors.push(y);
    }
    Ok(Some(RitzPairs {
        theta: order.iter().map(|&i| s[i]).collect(),
        vectors,
    }))
}
