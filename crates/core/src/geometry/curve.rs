//! The exact boundary curves: line segments and circular arcs, parametrised by `t ∈ [0, 1]`,
//! their closed-form intersections (line–line, line–circle, circle–circle), and the point
//! helpers (distances, rotation about a point) that the shapes share.

use super::Point;
use std::f64::consts::PI;

/// A boundary curve, parametrised by `t ∈ [0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Curve {
    /// Straight segment from `a` to `b`: `p(t) = a + t (b − a)`.
    Line {
        /// Start.
        a: Point,
        /// End.
        b: Point,
    },
    /// Circular arc `p(t) = c + ρ (cos φ, sin φ)`, `φ = start + t · sweep` (sweep > 0: counter-clockwise).
    Arc {
        /// Centre.
        center: Point,
        /// Radius ρ.
        radius: f64,
        /// Start angle \[rad\].
        start: f64,
        /// Signed sweep \[rad\], |sweep| ≤ 2π.
        sweep: f64,
    },
}

impl Curve {
    /// The point at parameter `t`.
    pub fn point(&self, t: f64) -> Point {
        match *self {
            Curve::Line { a, b } => [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
            Curve::Arc {
                center,
                radius,
                start,
                sweep,
            } => {
                let phi = start + t * sweep;
                [center[0] + radius * phi.cos(), center[1] + radius * phi.sin()]
            }
        }
    }

    /// Unit tangent times the speed `|dp/dt|` at `t`.
    pub fn derivative(&self, t: f64) -> Point {
        match *self {
            Curve::Line { a, b } => [b[0] - a[0], b[1] - a[1]],
            Curve::Arc {
                radius, start, sweep, ..
            } => {
                let phi = start + t * sweep;
                [-radius * sweep * phi.sin(), radius * sweep * phi.cos()]
            }
        }
    }

    /// Arc length.
    pub fn length(&self) -> f64 {
        match *self {
            Curve::Line { a, b } => dist(a, b),
            Curve::Arc { radius, sweep, .. } => radius * sweep.abs(),
        }
    }

    /// The same curve traversed backwards.
    pub fn reversed(&self) -> Curve {
        match *self {
            Curve::Line { a, b } => Curve::Line { a: b, b: a },
            Curve::Arc {
                center,
                radius,
                start,
                sweep,
            } => Curve::Arc {
                center,
                radius,
                start: start + sweep,
                sweep: -sweep,
            },
        }
    }

    /// The piece between parameters `t0 < t1`.
    pub fn sub(&self, t0: f64, t1: f64) -> Curve {
        match *self {
            Curve::Line { .. } => Curve::Line {
                a: self.point(t0),
                b: self.point(t1),
            },
            Curve::Arc {
                center,
                radius,
                start,
                sweep,
            } => Curve::Arc {
                center,
                radius,
                start: start + t0 * sweep,
                sweep: (t1 - t0) * sweep,
            },
        }
    }

    /// The curve rotated by `angle` about `pivot`.
    pub fn rotated(&self, pivot: Point, angle: f64) -> Curve {
        match *self {
            Curve::Line { a, b } => Curve::Line {
                a: rotate(a, pivot, angle),
                b: rotate(b, pivot, angle),
            },
            Curve::Arc {
                center,
                radius,
                start,
                sweep,
            } => Curve::Arc {
                center: rotate(center, pivot, angle),
                radius,
                start: start + angle,
                sweep,
            },
        }
    }

    /// Euclidean distance from `p` to the curve.
    pub fn distance(&self, p: Point) -> f64 {
        match *self {
            Curve::Line { a, b } => segment_distance(p, a, b),
            Curve::Arc {
                center,
                radius,
                start,
                sweep,
            } => {
                let d = [p[0] - center[0], p[1] - center[1]];
                let r = (d[0] * d[0] + d[1] * d[1]).sqrt();
                if r > 0.0 && angle_param(d[1].atan2(d[0]), start, sweep).is_some() {
                    (r - radius).abs()
                } else {
                    dist(p, self.point(0.0)).min(dist(p, self.point(1.0)))
                }
            }
        }
    }

    /// Parameters `t ∈ [0, 1]` where this curve meets `other`, paired with the parameter on `other`.
    pub fn intersections(&self, other: &Curve) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        match (*self, *other) {
            (Curve::Line { a, b }, Curve::Line { a: c, b: d }) => {
                let r = sub(b, a);
                let s = sub(d, c);
                let den = cross(r, s);
                if den.abs() > 1e-14 * dot(r, r).max(dot(s, s)) {
                    let t = cross(sub(c, a), s) / den;
                    let u = cross(sub(c, a), r) / den;
                    if in_unit(t) && in_unit(u) {
                        out.push((t.clamp(0.0, 1.0), u.clamp(0.0, 1.0)));
                    }
                }
            }
            (Curve::Line { .. }, Curve::Arc { .. }) => {
                out = other.intersections(self).into_iter().map(|(u, t)| (t, u)).collect();
            }
            (
                Curve::Arc {
                    center,
                    radius,
                    start,
                    sweep,
                },
                Curve::Line { a, b },
            ) => {
                // |a + u (b − a) − c|² = ρ²
                let d = sub(b, a);
                let f = sub(a, center);
                let qa = dot(d, d);
                let qb = 2.0 * dot(f, d);
                let qc = dot(f, f) - radius * radius;
                let disc = qb * qb - 4.0 * qa * qc;
                if qa > 0.0 && disc >= 0.0 {
                    let sq = disc.sqrt();
                    for u in [(-qb - sq) / (2.0 * qa), (-qb + sq) / (2.0 * qa)] {
                        if in_unit(u) {
                            let p = sub(other.point(u.clamp(0.0, 1.0)), center);
                            if let Some(t) = angle_param(p[1].atan2(p[0]), start, sweep) {
                                out.push((t, u.clamp(0.0, 1.0)));
                            }
                        }
                    }
                }
            }
            (
                Curve::Arc {
                    center: c0,
                    radius: r0,
                    start: s0,
                    sweep: w0,
                },
                Curve::Arc {
                    center: c1,
                    radius: r1,
                    start: s1,
                    sweep: w1,
                },
            ) => {
                let d = sub(c1, c0);
                let dd = d[0].hypot(d[1]);
                if dd > 1e-14 * (r0 + r1) && dd <= r0 + r1 && dd >= (r0 - r1).abs() {
                    let along = (r0 * r0 - r1 * r1 + dd * dd) / (2.0 * dd);
                    let h = (r0 * r0 - along * along).max(0.0).sqrt();
                    let m = [c0[0] + along * d[0] / dd, c0[1] + along * d[1] / dd];
                    for sgn in [-1.0, 1.0] {
                        let p = [m[0] - sgn * h * d[1] / dd, m[1] + sgn * h * d[0] / dd];
                        let p0 = sub(p, c0);
                        let p1 = sub(p, c1);
                        if let (Some(t), Some(u)) = (
                            angle_param(p0[1].atan2(p0[0]), s0, w0),
                            angle_param(p1[1].atan2(p1[0]), s1, w1),
                        ) {
                            out.push((t, u));
                        }
                        if h == 0.0 {
                            break;
                        }
                    }
                }
            }
        }
        out
    }
}

/// Parameter of angle `phi` on an arc starting at `start` with signed `sweep`, if on the arc.
pub(super) fn angle_param(phi: f64, start: f64, sweep: f64) -> Option<f64> {
    let rel = if sweep >= 0.0 { phi - start } else { start - phi };
    let rel = rel.rem_euclid(2.0 * PI);
    let w = sweep.abs();
    let eps = 1e-12;
    if rel <= w + eps {
        Some((rel / w).min(1.0))
    } else if 2.0 * PI - rel < eps {
        Some(0.0)
    } else {
        None
    }
}

pub(super) fn in_unit(t: f64) -> bool {
    (-1e-12..=1.0 + 1e-12).contains(&t)
}

pub(super) fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1]]
}

pub(super) fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

pub(super) fn cross(a: Point, b: Point) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

pub(super) fn dist(a: Point, b: Point) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

pub(super) fn rotate(p: Point, pivot: Point, angle: f64) -> Point {
    // Exact for multiples of 90° (sin π is 1.2e-16 in floating point, not 0).
    let snap = |v: f64| if v.abs() < 1e-15 { 0.0 } else { v };
    let (s, c) = angle.sin_cos();
    let (s, c) = (snap(s), snap(c));
    let d = sub(p, pivot);
    [pivot[0] + c * d[0] - s * d[1], pivot[1] + s * d[0] + c * d[1]]
}

/// Distance from `p` to the segment `a b`.
pub fn segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let t = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, [a[0] + t * ab[0], a[1] + t * ab[1]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_param_handles_wraparound_and_negative_sweeps() {
        assert_eq!(angle_param(0.5, 0.0, 1.0), Some(0.5));
        assert!(angle_param(-0.5, 0.0, 1.0).is_none());
        assert!((angle_param(-0.5, 0.0, -1.0).unwrap() - 0.5).abs() < 1e-15);
        assert!((angle_param(-3.0, 3.0, 1.0).unwrap() - (2.0 * PI - 6.0)).abs() < 1e-12);
    }
}
