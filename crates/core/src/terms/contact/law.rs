//! The penalty law of the wall: the energy density `ψ(g) = ½ k min(g, 0)²`, its secant over a
//! step and the secant's slope, and the smooth taper `s(η)` that fades the deformable face's
//! energy out past its ends.

use super::WallContact;

/// The taper `s(η)` of the face's ends (see the module doc).
pub(super) fn taper(eta: f64) -> f64 {
    let e = eta.clamp(0.0, 1.0);
    1.0 - e * e * (3.0 - 2.0 * e)
}

/// `s'(η)`.
pub(super) fn taper_slope(eta: f64) -> f64 {
    let e = eta.clamp(0.0, 1.0);
    -6.0 * e * (1.0 - e)
}

/// The secant of `s` between `e0` and `e1` (`s'` when they coincide), in closed form on one piece.
pub(super) fn taper_secant(e0: f64, e1: f64) -> f64 {
    let (c0, c1) = (e0.clamp(0.0, 1.0), e1.clamp(0.0, 1.0));
    if c0 == c1 {
        return if e0 == e1 { taper_slope(e0) } else { 0.0 };
    }
    if (c0 == e0) && (c1 == e1) {
        // both on the cubic: (s1 − s0)/(e1 − e0) without cancellation
        return -3.0 * (e0 + e1) + 2.0 * (e0 * e0 + e0 * e1 + e1 * e1);
    }
    (taper(e1) - taper(e0)) / (e1 - e0)
}

impl WallContact {
    pub(super) fn density(&self, g: f64) -> f64 {
        let pen = g.min(0.0);
        0.5 * self.stiffness * pen * pen
    }

    /// The secant of each point's energy density along its gap (see the module doc), `ψ'(g)` when
    /// the ends coincide \[N/m³·m = Pa\].
    pub fn secant(&self, g0: f64, g1: f64) -> f64 {
        let k = self.stiffness;
        if g0 <= 0.0 && g1 <= 0.0 {
            0.5 * k * (g0 + g1)
        } else if g0 >= 0.0 && g1 >= 0.0 {
            0.0
        } else {
            (self.density(g1) - self.density(g0)) / (g1 - g0)
        }
    }

    /// `∂ψ_d/∂g₁`, the derivative of the secant ([`WallContact::secant`]) with respect to the gap
    /// at the end of the step: `½ k` with both ends penetrating, 0 with both apart, and across the
    /// face `(ψ'(g₁) − ψ_d)/(g₁ − g₀)`, which is `k a (a + 2b) / (2 (a + b)²)` entering
    /// (`g₀ = b > 0`, `g₁ = −a`) and `k a² / (2 (a + b)²)` leaving (`g₀ = −a`, `g₁ = b`): never
    /// negative, and far from the `k` of the end-point Hessian when the point just crosses.
    pub(super) fn secant_slope(&self, g0: f64, g1: f64) -> f64 {
        let k = self.stiffness;
        if g0 <= 0.0 && g1 <= 0.0 {
            0.5 * k
        } else if g0 >= 0.0 && g1 >= 0.0 {
            0.0
        } else {
            (k * g1.min(0.0) - self.secant(g0, g1)) / (g1 - g0)
        }
    }
}
