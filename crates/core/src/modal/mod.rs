//! Modal analysis: natural frequencies and mode shapes of the linearised, constrained body.
//!
//! About a state `u₀` (here the undeformed one), small motions `u = u₀ + φ e^{iωt}` of the
//! undamped body obey
//!
//! ```text
//! K φ + Cᵀ μ = ω² M φ,        C φ = 0,
//! ```
//!
//! with `K` the tangent stiffness \[N/m\] (upper triangle on the fixed [`Pattern`]), `M` the
//! consistent mass matrix \[kg\] ([`MassMatrix`]), `C` linear constraint rows (the hinge's two
//! mean-displacement rows, [`crate::constraint::Hinge::dense_rows`], and any rows a caller adds)
//! and `μ` their multipliers \[N\]. Eigenvalues `λ = ω²` are in rad²/s², frequencies
//! `f = ω / 2π` in Hz; shapes are `M`-orthonormal, `φᵢᵀ M φⱼ = δᵢⱼ` (so `φ` is in m·kg^(−1/2)).
//!
//! **Method.** Shift-invert Lanczos ([`lanczos`]) about a shift `σ` \[rad²/s²\] below the lowest
//! eigenvalue: `A = K − σM` is then positive definite and factorised once by the sparse Cholesky
//! of [`crate::linsolve`]; the constraints are eliminated exactly in every application of
//! `(A, C)⁻¹` by their small Schur complement `C A⁻¹ Cᵀ` ([`constrained`]), so the iteration never
//! leaves `ker C` and nothing is ever dense beyond `m` columns. The pinned pendulum is free to
//! turn about the pivot: `K` has the rigid rotation as a null vector on `ker C` (`λ = 0`), which a
//! negative `σ` keeps off the factorisation; it is returned as the lowest pair (`λ ≈ 0`, see
//! [`Modes::rigid_count`]).
//!
//! **Limits.** One start vector: an eigenvalue of multiplicity `k > 1` is found once in exact
//! arithmetic and its other copies only through rounding, slowly (the pendulum's spectrum is
//! simple). Eigenvalues far above the shift lose accuracy: asking the tutorial's mesh for 100
//! pairs fails the backward-error check from about the 55th on (up to 3e-6) although the
//! recurrence counts them converged; up to 50 they pass at 2e-12 (`pendulum-fem modes` allows
//! at most 50). Slicing the spectrum with further shifts would lift this.
//!
//! **Checks.** Every returned pair is verified against the original problem: the residual
//! `‖Kφ − λMφ + Cᵀμ‖` (with the multipliers `μ` that minimise it) relative to
//! `‖(K − σM)φ‖ + |λ − σ| ‖Mφ‖` below [`RESIDUAL_TOLERANCE`], `|φᵢᵀMφⱼ − δᵢⱼ|` below
//! [`ORTHONORMALITY_TOLERANCE`] and `‖Cφ‖` below `10⁻¹⁰ ‖C‖ ‖φ‖`; a failure is an
//! [`Error::Modal`] naming the pair and the measured value.
//!
//! **Static solves.** [`constrained_static`] solves `K x + Cᵀμ = f`, `C x = 0` for several `f`
//! with one factorisation of `K + εD` (`D = diag K`, `ε = 10⁻¹⁰`) and iterative refinement with
//! the residuals of `K` itself, so `K` need only be positive definite on `ker C` (a pendulum whose
//! rotation is held by an extra row), not on the whole space.

use rayon::prelude::*;

use crate::assembly::Pattern;
use crate::error::Error;
use crate::linsolve::Cholesky;
use crate::model::Model;
use crate::terms::inertia::MassMatrix;
use crate::terms::{StepContext, Term};

pub mod constrained;
pub mod lanczos;

use constrained::{dot, ConstrainedSolver};

/// Largest backward error of a returned eigenpair (see the module doc).
pub const RESIDUAL_TOLERANCE: f64 = 1e-10;

/// Largest `|φᵢᵀMφⱼ − δᵢⱼ|` of the returned shapes.
pub const ORTHONORMALITY_TOLERANCE: f64 = 1e-8;

/// Eigenvalues at most this fraction of [`eigenvalue_scale`] count as rigid-body modes
/// ([`Modes::rigid_count`]). The rigid rotation comes out at rounding level (`~10⁻¹⁶` of the
/// scale); the lowest elastic mode of the tutorial's pendulum is `~10⁻⁷` of it, and a mesh
/// 100 times finer lowers that ratio by `10⁻⁴` at most.
pub const RIGID_TOLERANCE: f64 = 1e-11;

/// Lowest eigenpairs of `K φ = ω² M φ`, `C φ = 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct Modes {
    /// `ω²` \[rad²/s²\], ascending.
    pub eigenvalues: Vec<f64>,
    /// The shapes, `M`-orthonormal, each of length `ndof`.
    pub shapes: Vec<Vec<f64>>,
}

impl Modes {
    /// `f = √max(ω², 0) / 2π` \[Hz\] of every pair.
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.eigenvalues
            .iter()
            .map(|&l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect()
    }

    /// The number of leading pairs that are rigid-body motions: `|ω²| ≤ RIGID_TOLERANCE · scale`
    /// with `scale` = [`eigenvalue_scale`] of the problem.
    pub fn rigid_count(&self, scale: f64) -> usize {
        self.eigenvalues
            .iter()
            .take_while(|l| l.abs() <= RIGID_TOLERANCE * scale)
            .count()
    }
}

/// `max_i K_ii / M_ii` \[rad²/s²\]: the order of the largest eigenvalue of the discrete problem,
/// the scale of "zero" for the rigid modes.
pub fn eigenvalue_scale(pattern: &Pattern, stiffness: &[f64], mass: &MassMatrix) -> f64 {
    (0..pattern.n)
        .filter_map(|c| pattern.position(c, c))
        .filter(|&k| mass.values[k] > 0.0)
        .map(|k| stiffness[k] / mass.values[k])
        .fold(0.0, f64::max)
}

/// Lowest `n` eigenpairs of K φ = ω² M φ subject to C φ = 0 (rows of `constraints`), shift-invert
/// about `shift` \[rad²/s²\], which must lie below the lowest eigenvalue (negative for a body with
/// a rigid motion) so that `K − shift·M` is positive definite. Eigenvalues ascending (ω²,
/// rad²/s²), shapes M-orthonormal (φᵢᵀ M φⱼ = δᵢⱼ), each of length ndof.
pub fn constrained_modes(
    pattern: &Pattern,
    stiffness: &[f64],
    mass: &MassMatrix,
    constraints: &[Vec<f64>],
    n: usize,
    shift: f64,
) -> Result<Modes, Error> {
    constrained_modes_on(Cholesky::new(pattern)?, pattern, stiffness, mass, constraints, n, shift)
}

/// [`constrained_modes`] with the factorisation `chol`, a [`Cholesky::new`] of `pattern` or a
/// [`Cholesky::sibling`] of one: the symbolic analysis of a pattern made once serves several
/// problems on it.
pub fn constrained_modes_on(
    chol: Cholesky,
    pattern: &Pattern,
    stiffness: &[f64],
    mass: &MassMatrix,
    constraints: &[Vec<f64>],
    n: usize,
    shift: f64,
) -> Result<Modes, Error> {
    let ndof = pattern.n;
    if n == 0 {
        return Ok(Modes {
            eigenvalues: Vec::new(),
            shapes: Vec::new(),
        });
    }
    if !shift.is_finite() {
        return Err(Error::Modal(format!(
            "shift {shift}: must be a finite number of rad²/s²"
        )));
    }
    let free = ndof.saturating_sub(constraints.len());
    if n > free {
        return Err(Error::Modal(format!(
            "{n} modes asked for a problem with {free} free degrees of freedom ({ndof} unknowns, {} constraints)",
            constraints.len()
        )));
    }
    if mass.values.len() != pattern.nnz() || stiffness.len() != pattern.nnz() {
        return Err(Error::Modal(format!(
            "stiffness ({}) and mass ({}) values do not match the pattern's {} entries",
            stiffness.len(),
            mass.values.len(),
            pattern.nnz()
        )));
    }
    let a: Vec<f64> = stiffness.iter().zip(&mass.values).map(|(k, m)| k - shift * m).collect();
    let what = format!("K − σM with the shift σ = {shift:e} rad²/s²");
    let mut solver = ConstrainedSolver::new(chol, pattern, &a, constraints, &what).map_err(|e| match e {
        Error::Modal(m) if m.ends_with("not positive definite") => Error::Modal(format!(
            "{m}: the shift lies above the lowest eigenvalue; choose a shift below it (negative for a body free \
             to turn about its pivot)"
        )),
        e => e,
    })?;
    let max_steps = (4 * n + 40).max(80);
    let pairs = lanczos::largest(&mut solver, mass, ndof, free, n, max_steps)?;
    let mut modes: Vec<(f64, Vec<f64>)> = pairs
        .theta
        .iter()
        .zip(pairs.vectors)
        .map(|(&t, mut v)| {
            solver.project(&mut v);
            (shift + 1.0 / t, v)
        })
        .collect();
    modes.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (eigenvalues, shapes): (Vec<f64>, Vec<Vec<f64>>) = modes.into_iter().unzip();
    let modes = Modes { eigenvalues, shapes };
    check(pattern, stiffness, mass, constraints, shift, &modes)?;
    Ok(modes)
}

/// The multipliers `μ` minimising `‖r + Cᵀμ‖` (normal equations `C Cᵀ μ = −C r`) and that norm.
fn constrained_residual(constraints: &[Vec<f64>], r: &[f64]) -> f64 {
    let m = constraints.len();
    if m == 0 {
        return dot(r, r).sqrt();
    }
    let g = faer::Mat::<f64>::from_fn(m, m, |i, j| dot(&constraints[i], &constraints[j]));
    let b = faer::Mat::<f64>::from_fn(m, 1, |i, _| -dot(&constraints[i], r));
    let mu = match g.llt(faer::Side::Lower) {
        Ok(llt) => faer::linalg::solvers::Solve::solve(&llt, &b),
        Err(_) => return dot(r, r).sqrt(),
    };
    let mut res = r.to_vec();
    for (i, row) in constraints.iter().enumerate() {
        res.iter_mut().zip(row).for_each(|(x, c)| *x += c * mu[(i, 0)]);
    }
    dot(&res, &res).sqrt()
}

/// `‖A‖_∞`, the largest absolute row sum, of the symmetric matrix with upper-triangle `values`
/// (a bound of its 2-norm).
fn norm_inf(pattern: &Pattern, values: &[f64]) -> f64 {
    let mut rows = vec![0.0; pattern.n];
    for c in 0..pattern.n {
        for k in pattern.col_ptr[c]..pattern.col_ptr[c + 1] {
            let r = pattern.row_idx[k];
            rows[r] += values[k].abs();
            if r != c {
                rows[c] += values[k].abs();
            }
        }
    }
    rows.into_iter().fold(0.0, f64::max)
}

/// The largest backward error of the pairs, `‖Kφ − λMφ + Cᵀμ‖ / ((‖K‖ + |λ| ‖M‖) ‖φ‖)`
/// (`μ` minimising it, `∞`-norms of the matrices), their largest deviation from
/// `M`-orthonormality and their largest relative constraint violation `|c·φ| / (‖C‖ ‖φ‖)`.
pub fn verify(
    pattern: &Pattern,
    stiffness: &[f64],
    mass: &MassMatrix,
    constraints: &[Vec<f64>],
    modes: &Modes,
) -> [f64; 3] {
    let ndof = pattern.n;
    let mut worst = [0.0f64; 3];
    let c_norm = constraints.iter().map(|r| dot(r, r)).sum::<f64>().sqrt();
    let (k_norm, m_norm) = (norm_inf(pattern, stiffness), norm_inf(pattern, &mass.values));
    // each pair on the pool's threads: its residual, its constraint violation and M φ
    let per_pair: Vec<(f64, f64, Vec<f64>)> = modes
        .eigenvalues
        .par_iter()
        .zip(&modes.shapes)
        .map(|(&l, phi)| {
            let (mut kphi, mut mphi) = (vec![0.0; ndof], vec![0.0; ndof]);
            pattern.sym_matvec(stiffness, phi, &mut kphi);
            mass.apply(phi, &mut mphi);
            let r: Vec<f64> = kphi.iter().zip(&mphi).map(|(k, m)| k - l * m).collect();
            let phi_norm = dot(phi, phi).sqrt();
            let scale = (k_norm + l.abs() * m_norm) * phi_norm;
            let violation = constraints
                .iter()
                .map(|row| dot(row, phi).abs() / (c_norm * phi_norm))
                .fold(0.0, f64::max);
            (constrained_residual(constraints, &r) / scale, violation, mphi)
        })
        .collect();
    let mut mass_shapes = Vec::with_capacity(modes.shapes.len());
    for (residual, violation, mphi) in per_pair {
        worst[0] = worst[0].max(residual);
        worst[2] = worst[2].max(violation);
        mass_shapes.push(mphi);
    }
    for (i, mi) in mass_shapes.iter().enumerate() {
        for (j, phi) in modes.shapes.iter().enumerate().take(i + 1) {
            let target = if i == j { 1.0 } else { 0.0 };
            worst[1] = worst[1].max((dot(mi, phi) - target).abs());
        }
    }
    worst
}

/// [`verify`] against the tolerances; an [`Error::Modal`] names what failed.
fn check(
    pattern: &Pattern,
    stiffness: &[f64],
    mass: &MassMatrix,
    constraints: &[Vec<f64>],
    shift: f64,
    modes: &Modes,
) -> Result<(), Error> {
    let [residual, orthonormality, constraint] = verify(pattern, stiffness, mass, constraints, modes);
    if residual.is_nan() || residual > RESIDUAL_TOLERANCE {
        return Err(Error::Modal(format!(
            "eigenpair residual ‖Kφ − ω²Mφ + Cᵀμ‖ is {residual:.3e} of (‖K‖ + ω²‖M‖)‖φ‖ (allowed \
             {RESIDUAL_TOLERANCE:e}); the factorisation is too ill-conditioned for the shift {shift:e} rad²/s²"
        )));
    }
    if orthonormality.is_nan() || orthonormality > ORTHONORMALITY_TOLERANCE {
        return Err(Error::Modal(format!(
            "mode shapes not M-orthonormal: |φᵢᵀMφⱼ − δᵢⱼ| up to {orthonormality:.3e} (allowed \
             {ORTHONORMALITY_TOLERANCE:e})"
        )));
    }
    if constraint.is_nan() || constraint > 1e-10 {
        return Err(Error::Modal(format!(
            "mode shapes violate the constraints: ‖Cφ‖ up to {constraint:.3e} of ‖C‖‖φ‖ (allowed 1e-10)"
        )));
    }
    Ok(())
}

/// Regularisation `ε` of [`constrained_static`]'s factorised matrix `K + ε diag K`.
const STATIC_REGULARISATION: f64 = 1e-10;

/// Relative residual `‖f − Kx − Cᵀμ‖ / ‖f‖` at which [`constrained_static`]'s refinement stops
/// (it stops earlier, at `10⁻¹²`, if it gets there), and the largest it accepts when the
/// refinement stalls at rounding level; a stall above it is a singular `K` on `ker C` (whose
/// residual stays of the order of `‖f‖`). The rounding level of `K x` depends on the load: the
/// reduced body's gravity load in the frame (`M e_x`, balanced by the hinge rows) stalls at
/// 1.5e-9 on the tutorial mesh.
const STATIC_ACCEPTED: f64 = 1e-7;

/// Solves K x = f subject to C x = 0 for each right-hand side (K positive definite on ker C); one
/// factorisation (of `K + ε diag K`, refined iteratively against `K`, see the module doc).
pub fn constrained_static(
    pattern: &Pattern,
    stiffness: &[f64],
    constraints: &[Vec<f64>],
    rhs: &[Vec<f64>],
) -> Result<Vec<Vec<f64>>, Error> {
    constrained_static_on(Cholesky::new(pattern)?, pattern, stiffness, constraints, rhs)
}

/// [`constrained_static`] with the factorisation `chol` (see [`constrained_modes_on`]).
pub fn constrained_static_on(
    chol: Cholesky,
    pattern: &Pattern,
    stiffness: &[f64],
    constraints: &[Vec<f64>],
    rhs: &[Vec<f64>],
) -> Result<Vec<Vec<f64>>, Error> {
    let ndof = pattern.n;
    if stiffness.len() != pattern.nnz() {
        return Err(Error::Modal(format!(
            "static solve: {} stiffness values for a pattern of {} entries",
            stiffness.len(),
            pattern.nnz()
        )));
    }
    let mut a = stiffness.to_vec();
    for c in 0..ndof {
        if let Some(k) = pattern.position(c, c) {
            a[k] += STATIC_REGULARISATION * stiffness[k].abs();
        }
    }
    let mut solver = ConstrainedSolver::new(chol, pattern, &a, constraints, "K + ε diag K (static solve)")?;
    let mut out = Vec::with_capacity(rhs.len());
    let mut kx = vec![0.0; ndof];
    for (i, f) in rhs.iter().enumerate() {
        if f.len() != ndof {
            return Err(Error::Modal(format!(
                "static solve: right-hand side {i} has {} entries, the system {ndof}",
                f.len()
            )));
        }
        let f_norm = dot(f, f).sqrt();
        let mut x = vec![0.0; ndof];
        let mut mu = vec![0.0; constraints.len()];
        let mut previous = f64::INFINITY;
        for iteration in 0..100 {
            // r = f − K x − Cᵀμ
            pattern.sym_matvec(stiffness, &x, &mut kx);
            let mut r: Vec<f64> = f.iter().zip(&kx).map(|(f, k)| f - k).collect();
            for (row, &m) in constraints.iter().zip(&mu) {
                r.iter_mut().zip(row).for_each(|(ri, c)| *ri -= c * m);
            }
            let r_norm = dot(&r, &r).sqrt();
            if r_norm <= 1e-12 * f_norm || f_norm == 0.0 {
                break;
            }
            let stalled = iteration > 2 && r_norm > 0.5 * previous;
            if stalled && r_norm <= STATIC_ACCEPTED * f_norm {
                // rounding level: the products K x of the residual cancel large terms
                break;
            }
            if stalled || !r_norm.is_finite() || iteration == 99 {
                return Err(Error::Modal(format!(
                    "static solve of right-hand side {i}: the refinement stalls at a residual of {:.3e} of ‖f‖ \
                     after {iteration} iterations; K is not positive definite on ker C (a free rigid motion: add a \
                     constraint row that holds it)",
                    r_norm / f_norm
                )));
            }
            previous = r_norm;
            let dmu = solver.solve_in_place(&mut r);
            x.iter_mut().zip(&r).for_each(|(a, b)| *a += b);
            mu.iter_mut().zip(&dmu).for_each(|(a, b)| *a += b);
        }
        out.push(x);
    }
    Ok(out)
}

/// The elastic tangent stiffness of the pendulum at u = 0 (values on model.pattern; the model's
/// fixed dofs, if any, handled as the dynamics does: rows and columns zeroed with a unit
/// diagonal, [`crate::assembly::Dirichlet`]). The sum of every body's strain-energy Hessian at the
/// undeformed state; gravity, the torque and the wall's contact add nothing there.
///
/// With fixed dofs (a deformable wall's block) the unit diagonal rows keep their mass, so a
/// modal analysis of such a model also finds spurious modes near `ω² = 1/M_ii`; `pendulum-fem
/// modes` analyses the pendulum alone.
pub fn stiffness_at_rest(model: &Model) -> Vec<f64> {
    let ndof = model.pattern.n;
    let u = vec![0.0; ndof];
    let cx = StepContext::at(&u, 0.0, 0.0, None);
    let mut values = vec![0.0; model.pattern.nnz()];
    for body in &model.bodies {
        body.elastic.add_hessian(&u, &cx, &model.pattern, &mut values);
    }
    if !model.fixed.is_empty() {
        model.fixed.apply_matrix(&mut values);
    }
    values
}

/// A shift for the pendulum of `model` at rest: `−0.01 E / (ρ L²)` \[rad²/s²\] (`L` the largest
/// distance of a node from the pivot), two orders below the scale of the lowest elastic
/// eigenvalue of a slender body of length `L`, so that the rigid rotation (`ω² = 0`) and the low
/// elastic modes are well separated in the shift-inverted spectrum and `K − σM` is well
/// conditioned.
pub fn rest_shift(model: &Model) -> f64 {
    let m = &model.config.material;
    let l = model.length_scale();
    -0.01 * m.youngs_modulus / (m.density * l * l)
}
