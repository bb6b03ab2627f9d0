//! Rigid kinematics about the pivot (the origin): the best-fit angle of a displaced body, the
//! unwrapping of angles across the branch cut of `atan2`, and turning displacements rigidly. Below
//! the terms (the torque's hub angle, the contact's turned arc), Newton (its rotated frame) and
//! the post-processing; it uses only the element data.
//!
//! **Proxy angle** (the tutorial's `rigid_body_proxy`): with `r = X` the reference position
//! relative to the pivot,
//!
//! ```text
//! s = ∫ (r_x u_y − r_y u_x) dA / ∫ r·r dA,   c = ∫ r·(r + u) dA / ∫ r·r dA,   θ = atan2(s, c),
//! ```
//!
//! the best-fit rotation of the displaced body about the pivot. Both integrals are linear in `u`
//! and are precomputed as vectors (degree-6 rule, exact on curved P2 elements). `θ` is unwrapped
//! so that it stays continuous past ±180° ([`Unwrap`]).
//!
//! **Rates**: the same best-fit projection applied to the velocity and acceleration fields about the
//! current position `x = X + u`: `ω = ∫ x × v dA / ∫ x·x dA`, `α = ∫ x × a dA / ∫ x·x dA`; exact for a
//! rigid motion (`v = ω e_z × x`, `a = α e_z × x − ω² x`). The integrals use the consistent mass
//! matrix (exact for fields in the P2 space; uniform density cancels).

use crate::fe::for_each_point;
use crate::mesh::Mesh;
use crate::quadrature::TriangleRule;

/// `R(θ) y`: the vector `y` turned by `theta` \[rad\].
#[inline]
pub fn rotate(theta: f64, y: [f64; 2]) -> [f64; 2] {
    let (s, c) = theta.sin_cos();
    [c * y[0] - s * y[1], s * y[0] + c * y[1]]
}

/// `angle` wrapped into `[−π, π]` (the representative closest to 0, [`unwrap_near`]).
pub fn wrap_angle(angle: f64) -> f64 {
    unwrap_near(angle, 0.0)
}

/// Writes into `out` the displacements of `nodes` turned rigidly by `angle` \[rad\] about the
/// pivot (the origin) from `u`: `x' = R(angle) (X + u)`, `u' = x' − X`, with `X` from `reference`.
/// Each node's value is computed from `u` alone, so a node listed twice is turned once; the other
/// entries of `out` are left as they are.
pub fn turn_about_pivot(
    reference: &[[f64; 2]],
    u: &[f64],
    out: &mut [f64],
    nodes: impl IntoIterator<Item = usize>,
    angle: f64,
) {
    let (s, c) = angle.sin_cos();
    for n in nodes {
        let [x, y] = turned(reference[n], [u[2 * n], u[2 * n + 1]], (s, c));
        (out[2 * n], out[2 * n + 1]) = (x, y);
    }
}

/// The displacement of the point at `p` displaced by `u` and then turned about the pivot by the
/// angle of `(sin, cos)`: one node of [`turn_about_pivot`].
#[inline]
pub fn turned(p: [f64; 2], u: [f64; 2], (s, c): (f64, f64)) -> [f64; 2] {
    let x = [p[0] + u[0], p[1] + u[1]];
    [c * x[0] - s * x[1] - p[0], s * x[0] + c * x[1] - p[1]]
}

/// The linear functionals of the proxy angle.
#[derive(Clone, Debug)]
pub struct RigidProjection {
    /// `∂/∂u ∫ (r_x u_y − r_y u_x) dA`.
    pub sin_weights: Vec<f64>,
    /// `∂/∂u ∫ r·u dA`.
    pub cos_weights: Vec<f64>,
    /// `∫ r·r dA` \[m⁴\].
    pub polar: f64,
    /// `∫ dA` \[m²\].
    pub area: f64,
    /// `∫ r dA` \[m³\].
    pub first_moment: [f64; 2],
}

impl RigidProjection {
    /// Precomputes the functionals on `mesh` (pivot at the origin).
    pub fn new(mesh: &Mesh) -> Self {
        let ndof = 2 * mesh.num_nodes();
        let mut sin_weights = crate::assembly::written_zeros(ndof);
        let mut cos_weights = crate::assembly::written_zeros(ndof);
        let (mut polar, mut area, mut first_moment) = (0.0, 0.0, [0.0; 2]);
        for_each_point(mesh, &TriangleRule::degree6(), |e, n, x, w| {
            polar += (x[0] * x[0] + x[1] * x[1]) * w;
            area += w;
            first_moment[0] += x[0] * w;
            first_moment[1] += x[1] * w;
            for (a, &node) in mesh.triangles[e].iter().enumerate() {
                sin_weights[2 * node] -= x[1] * n[a] * w;
                sin_weights[2 * node + 1] += x[0] * n[a] * w;
                cos_weights[2 * node] += x[0] * n[a] * w;
                cos_weights[2 * node + 1] += x[1] * n[a] * w;
            }
        });
        Self {
            sin_weights,
            cos_weights,
            polar,
            area,
            first_moment,
        }
    }

    /// The proxy angle in `(−π, π]` \[rad\].
    pub fn angle(&self, u: &[f64]) -> f64 {
        let s: f64 = self.sin_weights.iter().zip(u).map(|(w, x)| w * x).sum();
        let c: f64 = self.cos_weights.iter().zip(u).map(|(w, x)| w * x).sum();
        best_fit_angle(self.polar + c, s, None)
    }
}

/// The best-fit rotation angle about the pivot of a displaced set of points \[rad\], from its two
/// moments `c = ∫ X·x` and `s = ∫ X × x` (reference positions `X`, current `x`; any positive
/// weighting): `atan2(s, c)`, in `(−π, π]` without a `reference`, else on the branch within π of
/// `reference` (`(c, s)` is turned by `−reference`, `atan2` taken, `reference` added back, so
/// that no large angle enters `atan2`). The proxy angle ([`RigidProjection::angle`]), the
/// torque's hub angle ([`crate::terms::torque::HubAngle::angle_near`]) and the turn between two
/// hub states in its discrete gradient (`c = z₀·z₁`, `s = z₀ × z₁`) are this of their moments.
pub fn best_fit_angle(c: f64, s: f64, reference: Option<f64>) -> f64 {
    match reference {
        None => s.atan2(c),
        Some(reference) => {
            let (sr, cr) = reference.sin_cos();
            // rotate (c, s) by −reference
            let (c1, s1) = (c * cr + s * sr, s * cr - c * sr);
            reference + s1.atan2(c1)
        }
    }
}

/// The angle equal to `angle` modulo 2π that is closest to `reference` \[rad\]: the one unwrapping
/// rule ([`Unwrap`] with the previous value, [`wrap_angle`] with 0).
pub fn unwrap_near(angle: f64, reference: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    angle + tau * ((reference - angle) / tau).round()
}

/// Keeps an angle continuous across the ±π branch cut of `atan2`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Unwrap {
    last: Option<f64>,
}

impl Unwrap {
    /// Starts from a known continuous value.
    pub fn starting_at(theta: f64) -> Self {
        Self { last: Some(theta) }
    }

    /// The continuous angle closest to the previous one that equals `wrapped` modulo 2π.
    pub fn next(&mut self, wrapped: f64) -> f64 {
        let value = match self.last {
            None => wrapped,
            Some(prev) => unwrap_near(wrapped, prev),
        };
        self.last = Some(value);
        value
    }
}

/// The product rule for differences of a turn from `θ₀` to `θ₁`:
/// `R₁ − R₀ = Δθ sinc(Δθ/2) R′(θ_m)` and `R̄ = ½(R₀ + R₁) = [rc −rs; rs rc]`, so that
/// `R₁y₁ − R₀y₀ = Δθ sc R′(θ_m) ȳ + R̄ (y₁ − y₀)` exactly.
#[derive(Clone, Copy)]
pub struct Turn {
    /// `sinc(Δθ/2)`.
    pub sc: f64,
    /// `sin θ_m`.
    pub sm: f64,
    /// `cos θ_m`.
    pub cm: f64,
    /// `R̄`'s `sin` entry.
    pub rs: f64,
    /// `R̄`'s `cos` entry.
    pub rc: f64,
}

impl Turn {
    /// The turn from `theta0` to `theta1` \[rad\].
    pub fn between(theta0: f64, theta1: f64) -> Self {
        let (sm, cm) = (0.5 * (theta0 + theta1)).sin_cos();
        let (s0, c0) = theta0.sin_cos();
        let (s1, c1) = theta1.sin_cos();
        Self {
            sc: sinc(0.5 * (theta1 - theta0)),
            sm,
            cm,
            rs: 0.5 * (s0 + s1),
            rc: 0.5 * (c0 + c1),
        }
    }
}

/// `sin(x)/x`.
fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-4 {
        1.0 - x * x / 6.0
    } else {
        x.sin() / x
    }
}
