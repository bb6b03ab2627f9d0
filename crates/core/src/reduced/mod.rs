//! The reduced body: a floating frame that turns about the pivot with the body, and a few elastic
//! modes in it (`[model] kind = "reduced"`).
//!
//! ## Kinematics
//!
//! With `X` the reference positions (pivot at the origin), `Φ` the `n` mode shapes in the frame
//! (columns over the pendulum's degrees of freedom), `q` \[√kg·m\] their amplitudes and `θ` \[rad\]
//! the frame's rotation, every point is at
//!
//! ```text
//! x = R(θ) (X + Φ q),       u = x − X,       ẋ = R(θ) (θ̇ J (X + Φ q) + Φ q̇),   J = [0 −1; 1 0].
//! ```
//!
//! The frame is fixed by three linear conditions on every mode: the hinge's two (the mean
//! displacement of the edge vanishes, [`crate::constraint::Hinge`]) and the mean-axis (Tisserand)
//! condition `(MJX)ᵀ Φ q = 0`: the frame turns with the body as a whole ([`basis`] says why). The
//! edge is centred on the pivot, so the full model's hinge holds exactly for every `(θ, q)`. The
//! torque acts on the hinge edge, whose best-fit rotation ([`crate::terms::torque::HubAngle`]) is
//! `θ_hub = θ + h·q` to first order in the strains: the actuator's energy is `−M(t) (θ + h·q)`.
//!
//! ## Energies (`M` the consistent mass matrix, the modes M-orthonormal: `ΦᵀMΦ = 1`)
//!
//! ```text
//! T = ½ θ̇² I(q) + θ̇ e(q)·q̇ + ½ |q̇|²,   I(q) = I₀ + 2 b·q + |q|²,   e(q) = d − G q,
//! I₀ = XᵀMX,  b = ΦᵀMX,  d = ΦᵀMJX,  G = ΦᵀJᵀMΦ (skew)                       [J]
//! V = ½ Σ λ_k q_k² − gᵀ R(θ) (S₀ + S q) − M(t) (θ + h·q) + Σ_p w_p ψ(g_p(θ, q))    [J]
//! S₀ = ∫ρt X dA = EᵀMX,   S = EᵀMΦ (E: the two unit translations),   g = (0, −g)
//! g_p = e_xᵀ R(θ) (X_p + Φ_p q) − x_w    (the wall's gap at the arc's quadrature point p)
//! ```
//!
//! The strain energy is the modes' linear one, `λ_k` the squared circular frequencies of the
//! basis (diagonal after a Rayleigh–Ritz step, [`basis`]). The kinetic energy is the full model's
//! `½ ẋᵀMẋ` of the reduced motion, exactly.
//!
//! ## Momenta and time stepping
//!
//! With `z = (θ, q)` and the mass matrix `𝕄(q) = [I(q) eᵀ; e 1]`, the momenta are `p = 𝕄(q) ż`
//! (`p_θ` is the angular momentum about the pivot). A step ([`step`]) conserves the energy
//! `T + V` and, where `V` does not depend on `θ`, `p_θ`, to the solver's tolerance whatever the
//! step; and since `θ` is a coordinate, a rigid
//! rotation (a free spin in its relative equilibrium, a spin-up by a constant torque) carries no
//! phase error from the scheme.
//!
//! A deformable wall is reduced beside the body ([`wall`]): its amplitudes join the step's
//! unknowns, and the contact couples the two through the full model's face term.

pub mod basis;
pub mod cache;
pub mod outputs;
mod patches;
pub mod step;
pub mod validity;
pub mod wall;

pub use basis::BasisSettings;
pub use outputs::{ProxyModes, StressModes};
pub use step::{Loads, StepReport};
pub use validity::{Validity, WARNING_BOUND};
pub use wall::ReducedWall;

use crate::modal::constrained::dot;

/// One quadrature point of the head's arc in modal form.
#[derive(Clone, Debug, PartialEq)]
pub struct ArcPoint {
    /// Reference position `X_p` \[m\].
    pub reference: [f64; 2],
    /// `Φ_p`: the point's displacement per unit amplitude of each mode, `x` then `y` rows.
    pub modes: [Vec<f64>; 2],
    /// Reference arc length times thickness \[m²\].
    pub weight: f64,
    /// `‖Φ_p‖` (Frobenius), bounding the elastic displacement of the point by `‖Φ_p‖ ‖q‖` \[1/√kg\].
    pub bound: f64,
}

impl ArcPoint {
    /// The point's position in the frame, `X_p + Φ_p q` \[m\].
    pub(crate) fn in_frame(&self, q: &[f64]) -> [f64; 2] {
        [
            self.reference[0] + dot(&self.modes[0], q),
            self.reference[1] + dot(&self.modes[1], q),
        ]
    }
}

/// The operators of a reduced body (see the module doc); built once per model.
#[derive(Clone, Debug, PartialEq)]
pub struct ReducedBody {
    /// The mode shapes `Φ` (M-orthonormal), each over the pendulum's degrees of freedom.
    pub shapes: Vec<Vec<f64>>,
    /// `λ_k`, the squared circular frequency of each mode \[rad²/s²\].
    pub stiffness: Vec<f64>,
    /// `I₀` \[kg m²\].
    pub inertia: f64,
    /// `b = ΦᵀMX`.
    pub b: Vec<f64>,
    /// `d = ΦᵀMJX`, zero to rounding in the mean-axis frame ([`basis`]).
    pub d: Vec<f64>,
    /// `h`: the hinge edge's best-fit rotation of each mode, so that the hub angle is `θ + h·q`.
    pub hub: Vec<f64>,
    /// `G = ΦᵀJᵀMΦ`, row-major, skew.
    pub g: Vec<f64>,
    /// `S₀ = EᵀMX` \[kg m\].
    pub s0: [f64; 2],
    /// `S = EᵀMΦ`, `x` then `y` rows.
    pub s: [Vec<f64>; 2],
    /// Total mass \[kg\].
    pub mass: f64,
    /// The arc's quadrature points (empty without a wall).
    pub arc: Vec<ArcPoint>,
    /// Reference positions, interleaved \[m\].
    pub reference: Vec<f64>,
    /// The full model's proxy-angle functionals of the modes.
    pub proxy: ProxyModes,
    /// The modes' element-node stresses.
    pub stress: StressModes,
}

/// The state of a reduced body: coordinates and their momenta.
#[derive(Clone, Debug, PartialEq)]
pub struct ReducedState {
    /// Frame rotation (the hub angle) \[rad\], unwrapped.
    pub theta: f64,
    /// Modal amplitudes \[√kg m\].
    pub q: Vec<f64>,
    /// Velocities `(θ̇, q̇)` \[rad/s, √kg m/s\].
    pub v: Vec<f64>,
    /// The deformable wall's amplitudes `r` \[√kg m\] ([`wall`]); empty without it.
    pub wall_q: Vec<f64>,
    /// Their velocities `ṙ` \[√kg m/s\].
    pub wall_v: Vec<f64>,
    /// The factorised step Jacobian the next step starts from ([`ReducedBody::step`]).
    pub jacobian: Option<step::Factor>,
}

pub(crate) use crate::rigid::rotate;

impl ReducedBody {
    /// Number of modes.
    pub fn modes(&self) -> usize {
        self.stiffness.len()
    }

    /// `e(q) = d − G q` into `e`.
    pub(crate) fn coupling(&self, q: &[f64], e: &mut [f64]) {
        let n = self.modes();
        for i in 0..n {
            let row = &self.g[i * n..(i + 1) * n];
            e[i] = self.d[i] - dot(row, q);
        }
    }

    /// `I(q)` \[kg m²\].
    pub(crate) fn inertia_at(&self, q: &[f64]) -> f64 {
        self.inertia + 2.0 * dot(&self.b, q) + dot(q, q)
    }

    /// The momenta `p = 𝕄(q) ż` of the velocities `w` (`e` a scratch of length `n`).
    pub(crate) fn momenta_into(&self, q: &[f64], w: &[f64], e: &mut [f64]) -> Vec<f64> {
        self.coupling(q, e);
        let n = e.len();
        let mut p = vec![0.0; n + 1];
        p[0] = self.inertia_at(q) * w[0] + dot(e, &w[1..]);
        for i in 0..n {
            p[1 + i] = e[i] * w[0] + w[1 + i];
        }
        p
    }

    /// The momenta `(p_θ, p_q) = 𝕄(q) ż` of a state (`p_θ` the angular momentum about the pivot
    /// \[kg m²/s\]).
    pub fn momenta(&self, s: &ReducedState) -> Vec<f64> {
        self.momenta_into(&s.q, &s.v, &mut vec![0.0; self.modes()])
    }

    /// The accelerations `z̈ = 𝕄⁻¹ (−∇V + ∂T/∂z − 𝕄̇ ż)` of a state under the potential gradient
    /// `grad_v` (`∂V/∂θ`, `∂V/∂q`):
    ///
    /// ```text
    /// rhs_θ = −∂V/∂θ − 2 θ̇ (b + q)·q̇,     rhs_q = −∂V/∂q + θ̇² (b + q) + 2 θ̇ G q̇,
    /// ```
    ///
    /// the bordered identity `𝕄` solved through its 1×1 Schur complement `I(q) − e·e`.
    pub fn accelerations(&self, s: &ReducedState, grad_v: &[f64]) -> Vec<f64> {
        let n = self.modes();
        let (q, v) = (&s.q, &s.v);
        let mut rhs = vec![0.0; n + 1];
        rhs[0] = -grad_v[0];
        for i in 0..n {
            let bq = self.b[i] + q[i];
            rhs[0] -= 2.0 * v[0] * bq * v[1 + i];
            let gq = dot(&self.g[i * n..(i + 1) * n], &v[1..]);
            rhs[1 + i] = -grad_v[1 + i] + v[0] * v[0] * bq + 2.0 * v[0] * gq;
        }
        let mut e = vec![0.0; n];
        self.coupling(q, &mut e);
        let at = (rhs[0] - dot(&e, &rhs[1..])) / (self.inertia_at(q) - dot(&e, &e));
        let mut a = rhs;
        a[0] = at;
        for i in 0..n {
            a[1 + i] -= e[i] * at;
        }
        a
    }

    /// `S₀ + S q` \[kg m\].
    pub(crate) fn first_moment(&self, q: &[f64]) -> [f64; 2] {
        [self.s0[0] + dot(&self.s[0], q), self.s0[1] + dot(&self.s[1], q)]
    }

    /// Kinetic energy \[J\].
    pub fn kinetic(&self, s: &ReducedState) -> f64 {
        0.5 * dot(&self.momenta(s), &s.v)
    }

    /// The hub angle `θ + h·q`, the hinge edge's best-fit rotation to first order in the strains \[rad\].
    pub fn hub_angle(&self, s: &ReducedState) -> f64 {
        s.theta + dot(&self.hub, &s.q)
    }

    /// Strain energy `½ Σ λ_k q_k²` \[J\].
    pub fn strain(&self, q: &[f64]) -> f64 {
        0.5 * self.stiffness.iter().zip(q).map(|(l, x)| l * x * x).sum::<f64>()
    }

    /// Gravitational energy `−gᵀ R(θ)(S₀ + S q)` for gravity `g` \[m/s²\] downwards \[J\].
    pub fn gravity(&self, s: &ReducedState, g: f64) -> f64 {
        // −(0, −g)·R s = g (R s)_y
        g * rotate(s.theta, self.first_moment(&s.q))[1]
    }

    /// The gap of arc point `p` to the face `x = face_x` \[m\].
    pub(crate) fn gap(&self, point: &ArcPoint, theta: f64, q: &[f64], face_x: f64) -> f64 {
        rotate(theta, point.in_frame(q))[0] - face_x
    }

    /// Linear momentum `P = R(θ)(θ̇ J (S₀ + S q) + S q̇)` \[kg m/s\].
    pub fn linear_momentum(&self, s: &ReducedState) -> [f64; 2] {
        let w = &s.v;
        let m = self.first_moment(&s.q);
        let local = [
            -w[0] * m[1] + dot(&self.s[0], &w[1..]),
            w[0] * m[0] + dot(&self.s[1], &w[1..]),
        ];
        rotate(s.theta, local)
    }

    /// The elastic displacement in the frame, `Φ q`, into `y` (interleaved).
    pub(crate) fn modal_sum(&self, q: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for (phi, &a) in self.shapes.iter().zip(q) {
            if a != 0.0 {
                y.iter_mut().zip(phi).for_each(|(v, f)| *v += a * f);
            }
        }
    }

    /// The full model's fields of a state: displacement `u = R(θ)(X + Φq) − X` and velocity
    /// `ẋ` (interleaved, over the pendulum's nodes) \[m, m/s\].
    pub fn fields(&self, s: &ReducedState, u: &mut [f64], v: &mut [f64]) {
        let w = &s.v;
        let nd = self.reference.len();
        let mut y = vec![0.0; nd];
        self.modal_sum(&s.q, &mut y);
        let mut yd = vec![0.0; nd];
        self.modal_sum(&w[1..], &mut yd);
        let turn = s.theta.sin_cos();
        for k in 0..nd / 2 {
            let y = [y[2 * k], y[2 * k + 1]];
            let yd = [yd[2 * k], yd[2 * k + 1]];
            self.place_node(k, turn, w[0], y, yd, u, v);
        }
    }

    /// [`ReducedBody::fields`] at the nodes `nodes` only (the same numbers): for the readers of a
    /// few nodes after every step (the wall's contact reads the head's arc).
    pub fn fields_at(&self, s: &ReducedState, nodes: &[usize], u: &mut [f64], v: &mut [f64]) {
        let w = &s.v;
        let turn = s.theta.sin_cos();
        // the sums of `modal_sum`, in its order
        let sum = |a: &[f64], d: usize| {
            let mut x = 0.0;
            for (phi, &c) in self.shapes.iter().zip(a) {
                if c != 0.0 {
                    x += c * phi[d];
                }
            }
            x
        };
        for &k in nodes {
            let y = [sum(&s.q, 2 * k), sum(&s.q, 2 * k + 1)];
            let yd = [sum(&w[1..], 2 * k), sum(&w[1..], 2 * k + 1)];
            self.place_node(k, turn, w[0], y, yd, u, v);
        }
    }

    /// Node `k`'s displacement and velocity from its elastic displacement `y` and velocity `yd` in
    /// the frame, the frame's turn `(sin θ, cos θ)` and rate `θ̇`.
    #[allow(clippy::too_many_arguments)]
    fn place_node(
        &self,
        k: usize,
        (sn, cs): (f64, f64),
        rate: f64,
        y: [f64; 2],
        yd: [f64; 2],
        u: &mut [f64],
        v: &mut [f64],
    ) {
        let (x0, x1) = (self.reference[2 * k], self.reference[2 * k + 1]);
        let p = [x0 + y[0], x1 + y[1]];
        u[2 * k] = cs * p[0] - sn * p[1] - x0;
        u[2 * k + 1] = sn * p[0] + cs * p[1] - x1;
        // θ̇ J p + Φ q̇ in the frame, then turned
        let l = [-rate * p[1] + yd[0], rate * p[0] + yd[1]];
        v[2 * k] = cs * l[0] - sn * l[1];
        v[2 * k + 1] = sn * l[0] + cs * l[1];
    }
}

impl ReducedBody {
    /// The initial state of the configuration's rigid start (as the full model's, see
    /// [`crate::simulation`]): angle `θ₀`, rate `ω₀`, and with `initial.elastic = "equilibrium"`
    /// the modes in equilibrium with gravity and the d'Alembert loads of the rigid motion at
    /// `α₀ = (τ_g + M(0)) / I₀`:
    ///
    /// ```text
    /// (Λ − ω₀² 1 − α₀ G) q = ω₀² b − α₀ d − g (sin θ₀ S_x + cos θ₀ S_y) + M(0) h
    /// ```
    ///
    /// (the modal equations of motion with `θ̈ = α₀`, `θ̇ = ω₀`, `q̇ = q̈ = 0`).
    pub fn initial_state(&self, config: &crate::config::Config, torque0: f64) -> ReducedState {
        use crate::config::{InitialAcceleration, InitialElastic};
        let init = &config.initial;
        let theta = init.angle_deg.to_radians();
        let omega = init.angular_velocity;
        let n = self.modes();
        let g = config.gravity.g;
        let (s, c) = theta.sin_cos();
        // the moment of gravity on the undeformed body about the pivot: −g (R S₀)_x
        let tau_g = -g * (c * self.s0[0] - s * self.s0[1]);
        let alpha = match init.acceleration {
            InitialAcceleration::Rigid => (tau_g + torque0) / self.inertia,
            InitialAcceleration::Zero => 0.0,
        };
        let mut q = vec![0.0; n];
        if init.elastic_state() == InitialElastic::Equilibrium {
            let mut a = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..n {
                    a[i * n + j] = -alpha * self.g[i * n + j];
                }
                a[i * n + i] += self.stiffness[i] - omega * omega;
                q[i] = omega * omega * self.b[i] - alpha * self.d[i] - g * (s * self.s[0][i] + c * self.s[1][i])
                    + torque0 * self.hub[i];
            }
            if !step::lu_solve(&mut a, n, &mut q) {
                q.iter_mut().for_each(|v| *v = 0.0);
            }
        }
        let mut v = vec![0.0; n + 1];
        v[0] = omega;
        ReducedState {
            theta,
            q,
            v,
            wall_q: Vec::new(),
            wall_v: Vec::new(),
            jacobian: None,
        }
    }
}
