//! One step of a reduced body: an energy-momentum rule for the Lagrangian
//! `½ żᵀ𝕄(q)ż − V(θ, q)` (the parent module's notation), solved by Newton's method for the end
//! velocities `v₁` (the `n + 1` unknowns; `z₁` follows from them).
//!
//! ```text
//! z₁ − z₀ = h ½ (v₀ + v₁)
//! 𝕄(q₁) v₁ − 𝕄(q₀) v₀ = −h (∂̄V − ½ ∇_q(v₀ᵀ𝕄(q)v₁)|_{q_m})        (the last term on q only)
//! ```
//!
//! * **Kinetic part.** For symmetric `𝕄`, `ΔT = Δp·v̄ − ½ v₀ᵀ(𝕄₁ − 𝕄₀)v₁` with `p = 𝕄v`,
//!   `v̄ = ½(v₀ + v₁)`. `𝕄` is quadratic in `q` (`I(q) = I₀ + 2b·q + |q|²`, `e(q) = d − Gq`), so
//!   `v₀ᵀ𝕄(q)v₁` is a quadratic polynomial in `q` and its gradient at the midpoint is an exact
//!   discrete gradient: `v₀ᵀΔ𝕄v₁ = ∇_q(v₀ᵀ𝕄v₁)|_{q_m}·Δq`, with
//!   `∇_q(aᵀ𝕄b) = 2 a_θ b_θ (b + q) + a_θ G b_q + b_θ G a_q` (the `b` of `I(q)` is the vector).
//!   No difference quotient of the kinetic energy is taken: nothing cancels.
//! * **Potential part**, each piece a discrete gradient of its own:
//!   the strain energy (quadratic) `λ q_m`; the torque `−τ̄ (1, h)` (`τ̄ = ½(M(t₀) + M(t₁))`, the
//!   full model's work `τ̄ Δθ_hub`, `θ_hub = θ + h·q`); gravity and the wall's gaps, both `aᵀ R(θ) y(q)` with `y` affine in
//!   `q`, by the product rule for differences, `a·(R₁y₁ − R₀y₀) = a·(R₁ − R₀) ȳ + a·R̄ (y₁ − y₀)`
//!   with `R₁ − R₀ = 2 sin(Δθ/2) R′(θ_m)`; each arc point's penalty density by its secant
//!   `ψ_d = (ψ(g₁) − ψ(g₀))/(g₁ − g₀)` along that gap ([`crate::terms::WallContact`]).
//!
//! So `E₁ − E₀ = Δp·Δz/h − ½ v₀ᵀΔ𝕄v₁ + ∂̄V·Δz = 0` (to the solver's tolerance). `𝕄` does not
//! depend on `θ`: when neither gravity nor the wall acts, `p_θ` changes by exactly `h τ̄`; and a
//! free spin in its relative equilibrium (`q̇ = 0`, `Λq = ω²(b + q)`) is a fixed point of the rule,
//! advancing `θ` by exactly `ω h`.

use super::wall::{Placed, ReducedWall};
use super::{rotate, ReducedBody, ReducedState};
use crate::modal::constrained::dot;
use crate::rigid::Turn;
use crate::terms::WallContact;

/// The loads of a step.
pub struct Loads<'a> {
    /// Gravity \[m/s²\], downwards.
    pub gravity: f64,
    /// The torque's mean over the step, `½ (M(t₀) + M(t₁))` \[N m\].
    pub torque: f64,
    /// The rigid wall, if any.
    pub wall: Option<&'a WallContact>,
    /// The deformable wall, reduced, and its contact with the head ([`super::wall`]), if any.
    pub block: Option<(&'a ReducedWall, &'a WallContact)>,
}

/// What a converged step reports besides its state.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepReport {
    /// Newton iterations.
    pub iterations: usize,
    /// The wall's mean force on the body over the step (global frame) \[N\].
    pub contact_force: [f64; 2],
}

/// Newton's method did not converge within its iterations.
#[derive(Clone, Copy, Debug)]
pub struct NotConverged {
    /// Iterations made.
    pub iterations: usize,
    /// The last scaled update.
    pub update: f64,
}

/// The end velocity of a linear oscillator `ẍ = −λ x + f` over a step `h` of the midpoint rule with
/// `f` held, from its start velocity `v0` and acceleration `a0`:
/// `v₁ (1 + c) = v₀ (1 − c) + h a₀`, `c = λ h²/4`.
fn oscillator_velocity(v0: f64, a0: f64, lambda: f64, h: f64) -> f64 {
    let c = 0.25 * lambda * h * h;
    (v0 * (1.0 - c) + h * a0) / (1.0 + c)
}

/// Largest Newton iterations of a step.
const MAX_ITERATIONS: usize = 30;

/// A step whose updates have not met the bound (`1e-12` of the velocities) after
/// [`MAX_ITERATIONS`] is accepted when its last update is within this factor of it (`1e-9` of the
/// velocities): its iterations stall at the rounding of the residual. A stiff contact with the
/// deformable block (1e14 N/m³, the tutorial's swing) stalled at 10 times the bound in its second
/// impact, whatever the step, and the run failed where the full model runs through.
const ROUNDING_STALL: f64 = 1e3;

/// Scratch vectors of the residual.
struct Scratch {
    e: Vec<f64>,
    qm: Vec<f64>,
    q1: Vec<f64>,
    grad: Vec<f64>,
    /// The deformable wall's end amplitudes and gradient, and the placed nodes of its contact.
    r1: Vec<f64>,
    grad_r: Vec<f64>,
    placed: Option<Placed>,
    /// Whether the head is clear of the block's face at the step's start ([`ReducedWall::surely_apart`]).
    apart0: bool,
}

impl Scratch {
    fn new(body: &ReducedBody, loads: &Loads, s0: &ReducedState) -> Self {
        let n = body.modes();
        let placed = loads.block.map(|(wall, _)| {
            let mut p = wall.workspace();
            wall.place_start(&mut p, s0.theta, &s0.q, &s0.wall_q);
            p
        });
        let apart0 = loads
            .block
            .is_some_and(|(wall, contact)| wall.surely_apart(body, s0.theta, &s0.q, &s0.wall_q, contact.face_x));
        let m = s0.wall_q.len();
        Self {
            e: vec![0.0; n],
            qm: vec![0.0; n],
            q1: vec![0.0; n],
            grad: vec![0.0; n],
            r1: vec![0.0; m],
            grad_r: vec![0.0; m],
            placed,
            apart0,
        }
    }
}

impl ReducedBody {
    /// `grad += scale ∇_q(aᵀ𝕄(q)b)` (see the module doc).
    fn form_gradient(&self, q: &[f64], a: &[f64], b: &[f64], scale: f64, grad: &mut [f64]) {
        let n = self.modes();
        for i in 0..n {
            let row = &self.g[i * n..(i + 1) * n];
            grad[i] +=
                scale * (2.0 * a[0] * b[0] * (self.b[i] + q[i]) + a[0] * dot(row, &b[1..]) + b[0] * dot(row, &a[1..]));
        }
    }

    /// `(∂V/∂θ, ∂V/∂q)` at a state (gravity, torque, strain and the wall).
    fn potential_gradient(&self, s0: &ReducedState, loads: &Loads) -> Vec<f64> {
        let n = self.modes();
        let mut grad = vec![0.0; n + 1];
        let (sn, cs) = s0.theta.sin_cos();
        grad[0] = -loads.torque;
        for i in 0..n {
            grad[1 + i] = self.stiffness[i] * s0.q[i] - loads.torque * self.hub[i];
        }
        if loads.gravity != 0.0 {
            let g = loads.gravity;
            let m = self.first_moment(&s0.q);
            grad[0] += g * (cs * m[0] - sn * m[1]);
            for i in 0..n {
                grad[1 + i] += g * (sn * self.s[0][i] + cs * self.s[1][i]);
            }
        }
        if let Some(wall) = loads.wall {
            for pt in &self.arc {
                let gap = self.gap(pt, s0.theta, &s0.q, wall.face_x);
                if gap >= 0.0 {
                    continue;
                }
                let c = pt.weight * wall.stiffness * gap;
                let y = pt.in_frame(&s0.q);
                grad[0] += c * (-sn * y[0] - cs * y[1]);
                for i in 0..n {
                    grad[1 + i] += c * (cs * pt.modes[0][i] - sn * pt.modes[1][i]);
                }
            }
        }
        grad
    }

    /// The step's residual for the end velocities `v1` into `r`; returns the wall's mean force on
    /// the body and sets `s.q1` to the end amplitudes.
    fn residual(
        &self,
        s0: &ReducedState,
        v1: &[f64],
        h: f64,
        loads: &Loads,
        s: &mut Scratch,
        r: &mut [f64],
    ) -> [f64; 2] {
        let n = self.modes();
        let (theta0, q0, v0) = (s0.theta, &s0.q[..], &s0.v[..]);
        let theta1 = theta0 + 0.5 * h * (v0[0] + v1[0]);
        for i in 0..n {
            s.q1[i] = q0[i] + 0.5 * h * (v0[1 + i] + v1[1 + i]);
            s.qm[i] = 0.5 * (q0[i] + s.q1[i]);
        }
        let (q1, qm) = (std::mem::take(&mut s.q1), std::mem::take(&mut s.qm));
        let mut grad = std::mem::take(&mut s.grad);
        // Δp = 𝕄(q₁)v₁ − 𝕄(q₀)v₀
        let (p1, p0) = (
            self.momenta_into(&q1, v1, &mut s.e),
            self.momenta_into(q0, v0, &mut s.e),
        );
        // the kinetic energy's discrete gradient: −½ ∇_q(v₀ᵀ𝕄v₁) at q_m
        grad.iter_mut().for_each(|g| *g = 0.0);
        self.form_gradient(&qm, v0, v1, -0.5, &mut grad);
        // the potential's discrete gradient
        let turn = Turn::between(theta0, theta1);
        let Turn { sc, sm, cm, rs, rc } = turn;
        for i in 0..n {
            grad[i] += self.stiffness[i] * qm[i] - loads.torque * self.hub[i];
        }
        let mut d_theta = -loads.torque;
        if loads.gravity != 0.0 {
            let g = loads.gravity;
            let sbar = self.first_moment(&qm);
            d_theta += g * sc * (cm * sbar[0] - sm * sbar[1]);
            for i in 0..n {
                grad[i] += g * (rs * self.s[0][i] + rc * self.s[1][i]);
            }
        }
        let mut force = [0.0; 2];
        if let Some(wall) = loads.wall {
            let qn = dot(q0, q0).max(dot(&q1, &q1)).sqrt();
            for pt in &self.arc {
                // a point whose rigid position at both ends clears the face by more than its
                // largest elastic displacement has no force
                let slack = pt.bound * qn;
                let r0 = rotate(theta0, pt.reference)[0] - wall.face_x;
                let r1 = rotate(theta1, pt.reference)[0] - wall.face_x;
                if r0 > slack && r1 > slack {
                    continue;
                }
                let g0 = self.gap(pt, theta0, q0, wall.face_x);
                let g1 = self.gap(pt, theta1, &q1, wall.face_x);
                let psi = wall.secant(g0, g1);
                if psi == 0.0 {
                    continue;
                }
                let c = pt.weight * psi;
                let y = pt.in_frame(&qm);
                d_theta += c * sc * (-sm * y[0] - cm * y[1]);
                for i in 0..n {
                    grad[i] += c * (rc * pt.modes[0][i] - rs * pt.modes[1][i]);
                }
                force[0] -= c;
            }
        }
        if let (Some((wall, contact)), Some(placed)) = (loads.block, s.placed.as_mut()) {
            // the block's rows: ṙ₁ − ṙ₀ + h (Λ r_m + w + Ψᵀ∇ᵈΠ_c)
            let (r0, rv0, rv1) = (&s0.wall_q, &s0.wall_v, &v1[n + 1..]);
            for k in 0..r0.len() {
                s.r1[k] = r0[k] + 0.5 * h * (rv0[k] + rv1[k]);
                s.grad_r[k] = wall.stiffness[k] * 0.5 * (r0[k] + s.r1[k]) + wall.weight[k];
            }
            // a head clear of the face at both ends has no contact force
            let apart = s.apart0 && wall.surely_apart(self, theta1, &q1, &s.r1, contact.face_x);
            if !apart {
                let face = wall.contact_gradient(
                    contact,
                    placed,
                    (theta1, turn),
                    &q1,
                    &qm,
                    &s.r1,
                    &mut grad,
                    &mut s.grad_r,
                );
                d_theta += face.theta;
                force[0] += face.force[0];
                force[1] += face.force[1];
            }
            for k in 0..r0.len() {
                r[n + 1 + k] = rv1[k] - rv0[k] + h * s.grad_r[k];
            }
        }
        r[0] = p1[0] - p0[0] + h * d_theta;
        for i in 0..n {
            r[1 + i] = p1[1 + i] - p0[1 + i] + h * grad[i];
        }
        (s.q1, s.qm, s.grad) = (q1, qm, grad);
        force
    }

    /// The Jacobian of the step's residual in `v₁` by forward differences, column by column,
    /// the step a 1e-7 of the velocities' scale (their size, their change, or the velocity the
    /// residual's impulse would give), into `jac` (row-major); `r` the residual at `v1`.
    #[allow(clippy::too_many_arguments)]
    fn jacobian(
        &self,
        s0: &ReducedState,
        v1: &mut [f64],
        r: &[f64],
        h: f64,
        loads: &Loads,
        s: &mut Scratch,
        jac: &mut [f64],
    ) {
        let m = v1.len();
        let inf = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |a, b| a.max(b.abs()));
        // θ̇ and q̇ have different units: a scale each, q̇'s at least √I θ̇ (the same kinetic
        // energy), so that the differences stay far above the roundings of stiff modes' rows
        let theta_scale = s0.v[0].abs().max(v1[0].abs()).max(r[0].abs() / self.inertia).max(1e-12);
        // the velocity change a residual would give: a mode's row weighs `1 + λ h²/4`
        let block = loads.block.map_or(&[][..], |(wall, _)| &wall.stiffness[..]);
        let impulse = r[1..]
            .iter()
            .zip(self.stiffness.iter().chain(block))
            .map(|(x, l)| x / (1.0 + 0.25 * l * h * h));
        let q_scale = inf(&mut s0.v[1..].iter().chain(&s0.wall_v).copied())
            .max(inf(&mut v1[1..].iter().copied()))
            .max(inf(&mut impulse.into_iter()))
            .max(self.inertia.sqrt() * theta_scale);
        let mut rp = vec![0.0; m];
        for j in 0..m {
            let delta = 1e-7 * if j == 0 { theta_scale } else { q_scale };
            let keep = v1[j];
            v1[j] = keep + delta;
            self.residual(s0, v1, h, loads, s, &mut rp);
            v1[j] = keep;
            for i in 0..m {
                jac[i * m + j] = (rp[i] - r[i]) / delta;
            }
        }
    }

    /// One step of length `h` from `s0` (see the module doc).
    ///
    /// **Newton's iterations** reuse the factorised Jacobian of an earlier step of the same length
    /// (`s0.jacobian`, kept in the state so that a restored snapshot replays bit for bit): the
    /// Jacobian (`≈ 𝕄 + h²/4 ∇²V`) changes little from step to step, and a chord iteration costs a
    /// residual and two triangular solves. It is made afresh (by forward differences) for a new
    /// step length, and whenever an iteration contracts the update by less than a factor 4.
    /// Converged: the update of `v₁` below `1e-12` of the velocities' scale (or exactly zero).
    pub fn step(&self, s0: &ReducedState, h: f64, loads: &Loads) -> Result<(ReducedState, StepReport), NotConverged> {
        let n = self.modes();
        // the pendulum's n + 1 velocities, then the deformable wall's
        let m = n + 1 + s0.wall_v.len();
        let v0: Vec<f64> = s0.v.iter().chain(&s0.wall_v).copied().collect();
        let mut s = Scratch::new(self, loads, s0);
        // predictor: the start's velocities and accelerations (the potential's gradient at the
        // start, from the discrete gradient of a step of length 0; the block's without contact)
        let mut v = {
            let grad = self.potential_gradient(s0, loads);
            let a = self.accelerations(s0, &grad);
            // each mode as a linear oscillator `q̈ = −λ q + f` under the midpoint rule,
            // `q̇₁ (1 + c) = q̇₀ (1 − c) + h q̈₀` with `c = λ h²/4`: explicit for the slow modes, and
            // the stiff ones (the contact patches', ω h ≫ 1) stay bounded instead of overshooting
            // by `ω h` (an impulse 1e9 times the step's, whose Jacobian by differences was useless)
            let mut v: Vec<f64> = (0..n + 1)
                .map(|i| match i {
                    0 => s0.v[0] + h * a[0],
                    _ => oscillator_velocity(s0.v[i], a[i], self.stiffness[i - 1], h),
                })
                .collect();
            // the block's rows without the contact, solved exactly by the same rule (the block's
            // modes are linear oscillators)
            if let Some((wall, _)) = loads.block {
                v.extend((0..wall.modes()).map(|k| {
                    let a = -(wall.stiffness[k] * s0.wall_q[k] + wall.weight[k]);
                    oscillator_velocity(s0.wall_v[k], a, wall.stiffness[k], h)
                }));
            }
            v
        };
        let mut r = vec![0.0; m];
        let mut factor = match &s0.jacobian {
            Some(j) if j.step == h && j.lu.len() == m * m => j.clone(),
            _ => Factor {
                step: h,
                lu: Vec::new(),
                pivots: Vec::new(),
            },
        };
        let mut update = f64::INFINITY;
        let mut previous = f64::INFINITY;
        for it in 1..=MAX_ITERATIONS {
            self.residual(s0, &v, h, loads, &mut s, &mut r);
            if factor.lu.is_empty() {
                let mut jac = vec![0.0; m * m];
                self.jacobian(s0, &mut v, &r, h, loads, &mut s, &mut jac);
                factor.lu = jac;
                if !lu_factor(&mut factor.lu, m, &mut factor.pivots) {
                    return Err(NotConverged { iterations: it, update });
                }
            }
            let mut dv: Vec<f64> = r.iter().map(|x| -x).collect();
            lu_apply(&factor.lu, m, &factor.pivots, &mut dv);
            if !dv.iter().all(|d| d.is_finite()) {
                return Err(NotConverged { iterations: it, update });
            }
            // the velocities' scale: θ̇ against θ̇ (or its change), q̇ against q̇, both floored by
            // the other's scale times the largest arm (q̇ ~ θ̇ √I)
            let wt = v[0].abs().max(v0[0].abs()).max((v[0] - v0[0]).abs());
            let wq = (1..m).map(|i| v[i].abs().max(v0[i].abs())).fold(0.0, f64::max);
            let floor = 1e-300;
            let ut = dv[0].abs() / (1e-12 * (wt + wq / self.inertia.sqrt()) + floor);
            let uq =
                dv[1..].iter().fold(0.0f64, |a, b| a.max(b.abs())) / (1e-12 * (wq + wt * self.inertia.sqrt()) + floor);
            for i in 0..m {
                v[i] += dv[i];
            }
            update = ut.max(uq);
            let stalled = it == MAX_ITERATIONS && update <= ROUNDING_STALL;
            if update <= 1.0 || dv.iter().all(|d| *d == 0.0) || stalled {
                let force = self.residual(s0, &v, h, loads, &mut s, &mut r);
                let wall_q = (0..m - n - 1)
                    .map(|k| s0.wall_q[k] + 0.5 * h * (s0.wall_v[k] + v[n + 1 + k]))
                    .collect();
                let wall_v = v.split_off(n + 1);
                let state = ReducedState {
                    theta: s0.theta + 0.5 * h * (s0.v[0] + v[0]),
                    q: (0..n).map(|i| s0.q[i] + 0.5 * h * (s0.v[1 + i] + v[1 + i])).collect(),
                    v,
                    wall_q,
                    wall_v,
                    jacobian: Some(factor),
                };
                return Ok((
                    state,
                    StepReport {
                        iterations: it,
                        contact_force: force,
                    },
                ));
            }
            // a slow contraction: the Jacobian afresh at the current iterate
            if update > 0.25 * previous {
                factor.lu.clear();
            }
            previous = update;
        }
        Err(NotConverged {
            iterations: MAX_ITERATIONS,
            update,
        })
    }
}

/// A factorised step Jacobian (LU with row pivots) and the step length it was made for.
#[derive(Clone, Debug, PartialEq)]
pub struct Factor {
    /// Step length \[s\].
    pub step: f64,
    /// `L` (unit diagonal, below) and `U` (on and above the diagonal), row-major.
    pub lu: Vec<f64>,
    /// The row swapped with each row in turn.
    pub pivots: Vec<usize>,
}

/// LU factorisation with partial pivoting in place; `false` if singular.
pub(crate) fn lu_factor(a: &mut [f64], n: usize, pivots: &mut Vec<usize>) -> bool {
    pivots.clear();
    for k in 0..n {
        let (mut piv, mut best) = (k, a[k * n + k].abs());
        for i in k + 1..n {
            let v = a[i * n + k].abs();
            if v > best {
                piv = i;
                best = v;
            }
        }
        if best == 0.0 || !best.is_finite() {
            return false;
        }
        pivots.push(piv);
        if piv != k {
            for j in 0..n {
                a.swap(k * n + j, piv * n + j);
            }
        }
        let d = a[k * n + k];
        for i in k + 1..n {
            let f = a[i * n + k] / d;
            a[i * n + k] = f;
            if f != 0.0 {
                for j in k + 1..n {
                    a[i * n + j] -= f * a[k * n + j];
                }
            }
        }
    }
    true
}

/// Solves with the factors of [`lu_factor`] in place.
pub(crate) fn lu_apply(lu: &[f64], n: usize, pivots: &[usize], b: &mut [f64]) {
    for k in 0..n {
        b.swap(k, pivots[k]);
        let v = b[k];
        if v != 0.0 {
            for i in k + 1..n {
                b[i] -= lu[i * n + k] * v;
            }
        }
    }
    for k in (0..n).rev() {
        let mut v = b[k];
        for j in k + 1..n {
            v -= lu[k * n + j] * b[j];
        }
        b[k] = v / lu[k * n + k];
    }
}

/// Solves `A x = b` in place (`b` becomes `x`, `a` its factors); `false` if singular.
pub(crate) fn lu_solve(a: &mut [f64], n: usize, b: &mut [f64]) -> bool {
    let mut pivots = Vec::with_capacity(n);
    if !lu_factor(a, n, &mut pivots) {
        return false;
    }
    lu_apply(a, n, &pivots, b);
    true
}
