//! When the head reaches the wall: the first touch of a rigid turn about the pivot (for the
//! step's length before an impact) and the first crossing along a step's straight path (to retake
//! a step that ended inside the wall).

use super::WallContact;

impl WallContact {
    /// The first time `s ∈ (0, h]` at which a point now apart reaches the wall when the body
    /// turns rigidly about the pivot (the origin) by `φ(s) = ω s + ½ α s²`, if any.
    ///
    /// A point at distance `ρ` from the pivot and polar angle `β` moves on the circle
    /// `x(φ) = ρ cos(β + φ)`; the wall's face at the point, `x_f = x − g` with `g` its gap now (the
    /// plane `x = x_w` for the rigid wall), is reached at `β + φ = ± arccos(x_f/ρ)` (mod 2π), the
    /// first such turn in either sense, and the turn at time `s` is the smallest positive root of
    /// `½ α s² + ω s = φ`. Exact on the circle for any turn: the nodes' own quadratic flight
    /// `x + s v + ½ s² a` cuts the circle's chord and, over a step that turns the body by a
    /// radian, missed touches or placed them late (a plate spun to 90 rad/s then ended its step
    /// millimetres inside a stiff wall). The body's own deformation in the meantime is not
    /// foreseen; a step that ends inside the wall anyway is retaken up to the crossing
    /// ([`WallContact::first_crossing`]).
    pub fn first_touch(&self, u: &[f64], omega: f64, alpha: f64, h: f64) -> Option<f64> {
        use std::f64::consts::TAU;
        // the smallest s in (0, h] with ½ α s² + ω s = phi
        let time_of = |phi: f64| -> Option<f64> {
            let (a, b, c) = (0.5 * alpha, omega, -phi);
            let roots = if a == 0.0 {
                [(b != 0.0).then(|| -c / b), None]
            } else {
                let disc = b * b - 4.0 * a * c;
                if disc < 0.0 {
                    [None, None]
                } else {
                    let q = -0.5 * (b + b.signum() * disc.sqrt());
                    [(q != 0.0).then(|| q / a), (q != 0.0).then(|| c / q)]
                }
            };
            roots
                .into_iter()
                .flatten()
                .filter(|s| *s > 0.0 && *s <= h && s.is_finite())
                .reduce(f64::min)
        };
        let mut first: Option<f64> = None;
        for p in &self.points {
            let g0 = self.gap(p, u);
            if g0 <= 0.0 || !g0.is_finite() {
                continue;
            }
            let at = |k: usize| (0..3).map(|a| p.basis[a] * u[2 * p.nodes[a] + k]).sum::<f64>();
            let (x, y) = (p.x_ref + at(0), p.y_ref + at(1));
            let rho = x.hypot(y);
            let c = (x - g0) / rho;
            if !(-1.0..=1.0).contains(&c) {
                continue; // the face is out of the point's reach
            }
            let beta = y.atan2(x);
            let target = c.acos();
            for t in [target, -target] {
                // the turns that bring the point there, counter-clockwise and clockwise
                let ccw = (t - beta).rem_euclid(TAU);
                for phi in [ccw, ccw - TAU] {
                    if let Some(s) = time_of(phi) {
                        first = Some(first.map_or(s, |f: f64| f.min(s)));
                    }
                }
            }
        }
        first
    }

    /// The first fraction `s ∈ (0, 1]` of the straight path from `u0` (apart) to `u1` at which a
    /// point reaches the wall, if any (the gap is linear in `u`).
    pub fn first_crossing(&self, u0: &[f64], u1: &[f64]) -> Option<f64> {
        self.points
            .iter()
            .filter_map(|p| {
                let (g0, g1) = (self.gap(p, u0), self.gap(p, u1));
                (g0 > 0.0 && g1 < 0.0).then(|| g0 / (g0 - g1))
            })
            .reduce(f64::min)
    }
}
