//! The actuator torque `M(t)` \[N·m\] at the pivot, applied through the hinge edge `Γ` (the
//! "rotation" boundary, `Y = 0`, centred on the pivot at the origin).
//!
//! ## Time profile
//!
//! The term keeps the `[torque]` section itself ([`config::Torque`], the one description of the
//! profile) and [`Torque::value`] evaluates its `M(t)`: `constant` (`A`), `step` (`A` for
//! `t ≥ start`, 0 before), `ramp` (0 before `start`, linear to `A` at `start + duration`, `A` after),
//! `sine` (`A sin(2π f (t − start) + phase)` for `t ≥ start`, 0 before) and `table` (a CSV
//! `time_s,torque_Nm`, [`TorqueTable`]: linear interpolation, constant extrapolation beyond both
//! ends; read once at set-up, every defect is an error naming the file and the line).
//!
//! ## Follower torque (`follower = true`, the default): the hub angle
//!
//! With reference points `X` on `Γ` and current points `x = X + u`, the best-fit rotation of the
//! hinge edge about the pivot (its "hub angle") is
//!
//! ```text
//! s(u) = ∫_Γ X × x ds = ∫_Γ (X_x u_y − X_y u_x) ds
//! c(u) = ∫_Γ X · x ds = ∫_Γ |X|² ds + ∫_Γ (X_x u_x + X_y u_y) ds
//! θ_hub(u) = atan2(s, c),
//! ```
//!
//! both linear in `u` with the weights `w_{a,i} = ∫_Γ X_i N_a ds` (three-point Gauss per quadratic
//! edge, as the hinge in [`crate::constraint`]; exact on straight edges). The torque is the energy
//!
//! ```text
//! Π_τ(u, t) = −M(t) θ_hub(u)                                        [J]
//! ∇Π_τ      = −M (c ∇s − s ∇c) / (c² + s²)                            [N]
//! ∇²Π_τ     = −M (θ_ss ∇s∇sᵀ + θ_sc (∇s∇cᵀ + ∇c∇sᵀ) + θ_cc ∇c∇cᵀ)   [N/m]
//! θ_ss = −2cs/r⁴,  θ_cc = 2cs/r⁴,  θ_sc = (s² − c²)/r⁴,  r² = c² + s².
//! ```
//!
//! Properties (tested in `tests/torque.rs`):
//!
//! * `θ_hub` is exact for a rigid rotation of *any* configuration: rotating every `x` by `δφ` rotates
//!   the pair `(c, s)` by `δφ` (read `c + i s = ∫ X̄ x ds` as complex numbers), so `θ_hub` grows by
//!   exactly `δφ`. The virtual work of the generalised force `f = −∇Π_τ = M ∇θ_hub` along the rigid
//!   virtual rotation `δu = δφ e_z × x` is therefore `M δφ`: its moment about the pivot,
//!   `Σ_a x_a × f_a`, is exactly `M(t)` at every angle and every deformation.
//! * Zero net force: a translation `δu = d` changes `s` by `(∫_Γ X ds) × d = 0` and `c` by
//!   `(∫_Γ X ds)·d = 0` because the edge is centred on the pivot, so `Σ_a f_a = 0`.
//! * The tangent `−M ∇²θ_hub` is symmetric and dense among the hinge-edge degrees of freedom; those
//!   pairs are listed in [`Term::hessian_entries`] and always written (zeros when `M = 0`).
//!
//! Why not the follower pressure load, the normal traction `t = M w(x) / ∫ w x ds` with the weight
//! `w = x / r_rod` on the current edge (`∫ w x ds = 2 r_rod²/3 = 1.5e-4 m²` for the tutorial)? A
//! traction that turns with the body is not the gradient of any potential: its tangent is not
//! symmetric (the Cholesky factorisation of [`crate::linsolve`] needs a symmetric one) and there is
//! no energy for the line search of [`crate::newton`]. `Π_τ` gives the same resultant (a pure couple
//! `M`, no net force), the same traction at the reference position (`∇θ_hub = ∇s / c₀` at `u = 0`,
//! i.e. `t_y = M X_x / ∫ X_x² ds`), and is conservative.
//!
//! **Continuity.** `atan2` jumps at ±π, so `Π_τ` would jump by `2πM` when the pendulum turns
//! through ±180°. `θ_hub` is evaluated relative to a reference angle `φ_ref` close to the current
//! configuration: `(c, s)` is rotated by `−φ_ref`, `atan2` taken, `φ_ref` added back. `φ_ref` is
//! `θ_hub` of the step's start state on the branch of the unwrapped proxy angle there, both from
//! the [`StepContext`] (the term keeps no state); within a step (rotations of much less than π) the
//! energy is smooth. Gradient and Hessian do not depend on `φ_ref`.
//!
//! **Input.** The torque's value is the held input of the context (`StepContext::torque`, set by
//! [`crate::simulation::Simulation::set_torque`]) when there is one, else the profile's `M(t)`.
//!
//! ## Fixed-direction load (`follower = false`)
//!
//! The hinge-edge traction `t_y = M(t) X_x / ∫_Γ X_x² ds` in the fixed global `y` direction, a linear
//! load `Π = −Σ_a f_a·u_a` with `f_{a,y} = M(t) w_{a,x} / ∫_Γ X_x² ds`, `f_{a,x} = 0`. It is
//! conservative with zero net force; its moment about the pivot is `M` in the reference position and
//! `M cos θ` once the body has turned by `θ` (`x_x = X_x cos θ` on the rotated edge): the fading
//! drive of a load that does not turn with the body.
//!
//! ## Work
//!
//! [`Term::external_work`] gives the work of the load over a step \[J\]: for the follower the work
//! of a couple along the computed motion, `½ (M_n + M_{n+1}) (θ_hub,n+1 − θ_hub,n)` (exact in `θ`
//! for a constant `M`); for the fixed load `½ (f_n + f_{n+1})·(u_{n+1} − u_n)` (exact for a constant
//! `M`, it is a potential). `Δ(kinetic + strain + gravity)` equals the accumulated work up to the
//! energy error of the time integrator. The average-acceleration rule balances the discrete kinetic
//! energy against `½ (f_n + f_{n+1})·Δu` of *all* forces; for a body turning by `Δφ` per step that
//! differs from the exact work by `M (Δφ − sin Δφ) ≈ M Δφ³/6` for the torque and by
//! `½ (1 − cos Δφ) ΔV ≈ M Δφ³/2` for the elastic forces (`V = Σ x·∇Π_el`, growing with the
//! centripetal tension as `I ω²`). Spun up from rest by a constant torque, the total energy lags
//! the work by about `Δφ_end²/3` of it (`Δφ_end` the last rotation per step): negligible for a
//! swinging pendulum, 1e-3 at `Δφ_end ≈ 0.055` rad per step.

mod hub;
mod limit;
mod profile;

pub use hub::HubAngle;
pub use limit::HUB_STRESS_LIMIT;
pub use profile::TorqueTable;

use super::{StepContext, StepStart, Term};
use crate::assembly::Pattern;
use crate::config;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::rigid::best_fit_angle;

/// How the torque load acts (`torque.follower`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TorqueMode {
    /// `Π = −M θ_hub(u)`: a pure couple `M` at every angle.
    Follower,
    /// Linear load in the fixed `y` direction: moment `M cos θ`.
    Fixed,
}

/// The actuator torque as an energy term (see the module doc).
#[derive(Debug)]
pub struct Torque {
    /// The `[torque]` section it was built from: the time profile `M(t)` and `follower`.
    pub profile: config::Torque,
    /// The samples of `profile.file` for `profile = "table"`, read once at set-up.
    pub table: Option<TorqueTable>,
    /// Hinge-edge weights.
    pub hub: HubAngle,
    /// Global degrees of freedom of the hinge edge, `[2n, 2n+1]` per node of `hub.nodes`.
    pub dofs: Vec<usize>,
}

impl Torque {
    /// The torque described by the `[torque]` section acting through boundary `name` of `mesh`;
    /// reads the table file for `profile = "table"`.
    pub fn from_config(mesh: &Mesh, name: &str, cfg: &config::Torque) -> Result<Self, Error> {
        use config::TorqueProfile as P;
        if cfg.profile == P::Ramp && cfg.duration <= 0.0 {
            return Err(Error::Config(format!(
                "torque.duration = {}: allowed duration > 0 s for profile = \"ramp\"",
                cfg.duration
            )));
        }
        let table = if cfg.profile == P::Table {
            let path = cfg.file.as_ref().ok_or_else(|| {
                Error::Config("torque.file: required for profile = \"table\" (a CSV time_s,torque_Nm)".into())
            })?;
            Some(TorqueTable::read(path)?)
        } else {
            None
        };
        let hub = HubAngle::new(mesh, name)?;
        let dofs = hub.nodes.iter().flat_map(|&n| [2 * n, 2 * n + 1]).collect();
        Ok(Self {
            profile: cfg.clone(),
            table,
            hub,
            dofs,
        })
    }

    /// Follower or fixed direction (`torque.follower`).
    pub fn mode(&self) -> TorqueMode {
        if self.profile.follower {
            TorqueMode::Follower
        } else {
            TorqueMode::Fixed
        }
    }

    /// The torque `M` \[N m\] at time `t` of the context's step: the held input, else the profile.
    pub fn moment_at(&self, t: f64, cx: &StepContext) -> f64 {
        cx.torque.unwrap_or_else(|| self.value(t))
    }

    /// `θ_hub` at the start of the context's step, on the branch of the unwrapped proxy angle
    /// `cx.theta0` (`φ_ref` of the module doc) \[rad\].
    pub fn start_angle(&self, cx: &StepContext) -> f64 {
        self.hub.angle_near(cx.u0, cx.theta0)
    }

    /// `θ_hub(u)` on the branch of the start of the context's step \[rad\].
    pub fn hub_angle(&self, u: &[f64], cx: &StepContext) -> f64 {
        self.hub.angle_near(u, self.start_angle(cx))
    }

    /// The generalised force `f = −∂Π/∂u` of a torque `m` \[N m\] on the hinge-edge degrees of
    /// freedom ([`Torque::dofs`]) \[N\].
    pub fn local_force(&self, u: &[f64], m: f64) -> Vec<f64> {
        match self.mode() {
            TorqueMode::Follower => self.hub.gradient_local(u).into_iter().map(|g| m * g).collect(),
            TorqueMode::Fixed => self.hub.wx.iter().flat_map(|w| [0.0, m * w / self.hub.xx]).collect(),
        }
    }

    /// The moment about the pivot of the generalised force, `Σ_a x_a × f_a` with `x = X + u` \[N·m\].
    pub fn moment_about_pivot(&self, u: &[f64], m: f64) -> f64 {
        let f = self.local_force(u, m);
        self.hub
            .nodes
            .iter()
            .zip(&self.hub.positions)
            .enumerate()
            .map(|(k, (&n, p))| {
                let x = [p[0] + u[2 * n], p[1] + u[2 * n + 1]];
                x[0] * f[2 * k + 1] - x[1] * f[2 * k]
            })
            .sum()
    }

    /// `½ (M(t0) + M(t1)) (θ_hub(u1) − θ_hub(u0))` \[J\]: the work of the follower torque over the
    /// context's step measured on the hub angle (`u1` within π of `u0`).
    pub fn angle_work(&self, u1: &[f64], cx: &StepContext) -> f64 {
        let th0 = self.start_angle(cx);
        let th1 = self.hub.angle_near(u1, th0);
        0.5 * (self.moment_at(cx.t0, cx) + self.moment_at(cx.t, cx)) * (th1 - th0)
    }
}

impl Term for Torque {
    fn name(&self) -> &'static str {
        "torque"
    }

    fn energy(&self, u: &[f64], cx: &StepContext) -> f64 {
        let m = self.moment_at(cx.t, cx);
        match self.mode() {
            TorqueMode::Follower => -m * self.hub_angle(u, cx),
            TorqueMode::Fixed => {
                let uy: f64 = self
                    .hub
                    .nodes
                    .iter()
                    .zip(&self.hub.wx)
                    .map(|(&n, w)| w * u[2 * n + 1])
                    .sum();
                -m * uy / self.hub.xx
            }
        }
    }

    fn add_gradient(&self, u: &[f64], cx: &StepContext, g: &mut [f64]) {
        for (d, f) in self.dofs.iter().zip(self.local_force(u, self.moment_at(cx.t, cx))) {
            g[*d] -= f;
        }
    }

    fn add_hessian(&self, u: &[f64], cx: &StepContext, pattern: &Pattern, values: &mut [f64]) {
        if self.mode() == TorqueMode::Fixed {
            return;
        }
        let m = self.moment_at(cx.t, cx);
        let (c, s) = self.hub.cos_sin(u);
        let r2 = c * c + s * s;
        let r4 = r2 * r2;
        let (t_ss, t_cc, t_sc) = (-2.0 * c * s / r4, 2.0 * c * s / r4, (s * s - c * c) / r4);
        let nd = self.dofs.len();
        let mut gs = vec![0.0; nd];
        let mut gc = vec![0.0; nd];
        for k in 0..self.hub.nodes.len() {
            gs[2 * k] = -self.hub.wy[k];
            gs[2 * k + 1] = self.hub.wx[k];
            gc[2 * k] = self.hub.wx[k];
            gc[2 * k + 1] = self.hub.wy[k];
        }
        for i in 0..nd {
            for j in i..nd {
                let h = t_ss * gs[i] * gs[j] + t_sc * (gs[i] * gc[j] + gc[i] * gs[j]) + t_cc * gc[i] * gc[j];
                let pos = pattern
                    .position(self.dofs[i], self.dofs[j])
                    .expect("torque Hessian entries are in the pattern (Term::hessian_entries)");
                values[pos] -= m * h;
            }
        }
    }

    fn hessian_entries(&self) -> Vec<(usize, usize)> {
        if self.mode() == TorqueMode::Fixed {
            return Vec::new();
        }
        super::dense_block(&self.dofs)
    }

    /// Follower: `−M̄ ∇ᵈθ_hub` with `M̄ = ½(M(t₀) + M(t₁))` and the discrete gradient of the hub
    /// angle in the plane of `z = (c, s)` (Gonzalez's formula for the polar angle):
    /// `∇ᵈθ = ∇θ(z_m) + (Δθ − ∇θ(z_m)·Δz)/|Δz|² Δz`, `∇θ(z) = (−s, c)/|z|²`, so that
    /// `∇ᵈθ · Δz = Δθ` and the work is exactly `M̄ Δθ_hub` ([`Torque::angle_work`]); then
    /// `∂θ/∂u = a ∇c + b ∇s` as in [`HubAngle::gradient_local`]. Fixed direction: the mean of the
    /// two end loads (work `½(f₀ + f₁)·Δu`).
    fn add_discrete_gradient(
        &self,
        start: &StepStart,
        u1: &[f64],
        cx: &StepContext,
        factor: f64,
        g: &mut [f64],
    ) -> f64 {
        let u0 = start.u;
        let (m0, m1) = (self.moment_at(cx.t0, cx), self.moment_at(cx.t, cx));
        let m_mean = 0.5 * (m0 + m1);
        match self.mode() {
            TorqueMode::Fixed => {
                let (f0, f1) = (self.local_force(u0, m0), self.local_force(u1, m1));
                for (k, &d) in self.dofs.iter().enumerate() {
                    g[d] -= factor * 0.5 * (f0[k] + f1[k]);
                }
            }
            TorqueMode::Follower => {
                let (c0, s0) = self.hub.cos_sin(u0);
                let (c1, s1) = self.hub.cos_sin(u1);
                // the turn from z₀ to z₁, exact to rounding (no large absolute angles involved)
                let dth = best_fit_angle(c0 * c1 + s0 * s1, c0 * s1 - s0 * c1, None);
                let (cm, sm) = (0.5 * (c0 + c1), 0.5 * (s0 + s1));
                let rm2 = cm * cm + sm * sm;
                let (mut a, mut b) = (-sm / rm2, cm / rm2);
                let dz = [c1 - c0, s1 - s0];
                let lin = a * dz[0] + b * dz[1];
                let numerator = dth - lin;
                let norm2 = dz[0] * dz[0] + dz[1] * dz[1];
                if numerator.abs() > 64.0 * f64::EPSILON * (dth.abs() + lin.abs()) && norm2 > 0.0 {
                    a += numerator / norm2 * dz[0];
                    b += numerator / norm2 * dz[1];
                }
                for k in 0..self.hub.nodes.len() {
                    let (wx, wy) = (self.hub.wx[k], self.hub.wy[k]);
                    // ∇c = (wx, wy), ∇s = (−wy, wx)
                    g[self.dofs[2 * k]] -= factor * m_mean * (a * wx - b * wy);
                    g[self.dofs[2 * k + 1]] -= factor * m_mean * (a * wy + b * wx);
                }
            }
        }
        self.energy(u1, cx)
    }

    fn external_work(&self, u1: &[f64], cx: &StepContext) -> f64 {
        if self.mode() == TorqueMode::Follower {
            return self.angle_work(u1, cx);
        }
        let u0 = cx.u0;
        let f0 = self.local_force(u0, self.moment_at(cx.t0, cx));
        let f1 = self.local_force(u1, self.moment_at(cx.t, cx));
        self.dofs
            .iter()
            .enumerate()
            .map(|(k, &d)| 0.5 * (f0[k] + f1[k]) * (u1[d] - u0[d]))
            .sum()
    }
}
