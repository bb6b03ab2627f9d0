//! Quadrature rules on the reference triangle `(0,0), (1,0), (0,1)` (area ½) and on `[0, 1]`.
//!
//! Each rule declares the total polynomial degree it integrates exactly; the tests check exactly
//! that with `∫_T̂ ξ^p η^q = p! q! / (p + q + 2)!`. The triangle rules are the symmetric rules of
//! Dunavant (1985): 6 points of degree 4 (used for the elastic energy, the FE default) and 12 points
//! of degree 6 (used where an integrand is a polynomial of degree 6 on curved elements: mass,
//! gravity and the rigid-body moments).

/// A quadrature rule on the reference triangle.
#[derive(Clone, Debug)]
pub struct TriangleRule {
    /// Points `[ξ, η]`.
    pub points: Vec<[f64; 2]>,
    /// Weights; they sum to the reference area ½.
    pub weights: Vec<f64>,
    /// Polynomials of total degree ≤ `degree` are integrated exactly.
    pub degree: usize,
}

impl TriangleRule {
    /// Builds a symmetric rule from orbits `(weight, a, b)` with barycentric points `(a, a, b)`
    /// (3 permutations; `a = b = ⅓` gives the centroid) or `(weight, a, b, c)` (6 permutations).
    fn from_orbits(three: &[(f64, f64)], six: &[(f64, f64, f64)], degree: usize) -> Self {
        let mut points = Vec::new();
        let mut weights = Vec::new();
        for &(w, a) in three {
            let b = 1.0 - 2.0 * a;
            for p in [[a, a], [a, b], [b, a]] {
                points.push(p);
                weights.push(0.5 * w);
            }
        }
        for &(w, a, b) in six {
            let c = 1.0 - a - b;
            for p in [[a, b], [b, a], [a, c], [c, a], [b, c], [c, b]] {
                points.push(p);
                weights.push(0.5 * w);
            }
        }
        Self {
            points,
            weights,
            degree,
        }
    }

    /// 6 points, degree 4.
    pub fn degree4() -> Self {
        Self::from_orbits(
            &[
                (0.223_381_589_678_011, 0.445_948_490_915_965),
                (0.109_951_743_655_322, 0.091_576_213_509_771),
            ],
            &[],
            4,
        )
    }

    /// 12 points, degree 6.
    pub fn degree6() -> Self {
        Self::from_orbits(
            &[
                (0.116_786_275_726_379, 0.249_286_745_170_910),
                (0.050_844_906_370_207, 0.063_089_014_491_502),
            ],
            &[(0.082_851_075_618_374, 0.053_145_049_844_817, 0.310_352_451_033_784)],
            6,
        )
    }

    /// Iterates over `(point, weight)`.
    pub fn iter(&self) -> impl Iterator<Item = ([f64; 2], f64)> + '_ {
        self.points.iter().copied().zip(self.weights.iter().copied())
    }
}

/// Three-point Gauss–Legendre rule on `[0, 1]` (degree 5): `(s, weight)`.
pub const GAUSS3_UNIT: [(f64, f64); 3] = [
    (0.112_701_665_379_258_3, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

/// The `n`-point Gauss–Legendre rule on `[0, 1]` (exact for polynomials of degree `2n − 1`):
/// `(s, weight)`, weights summing to 1. The roots of `P_n` by Newton's method from the usual
/// starting guesses `cos(π (i − ¼)/(n + ½))`, the weights `2/((1 − x²) P_n'(x)²)`, both mapped from
/// `[−1, 1]`.
pub fn gauss_legendre_unit(n: usize) -> Vec<(f64, f64)> {
    assert!(n >= 1, "a rule needs at least one point");
    let mut out = Vec::with_capacity(n);
    for i in 1..=n {
        let mut x = (std::f64::consts::PI * (i as f64 - 0.25) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_n(x) and P_n'(x) by the three-term recurrence
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                (p0, p1) = (p1, p2);
            }
            let pn = if n == 1 { x } else { p1 };
            let pm = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (x * pn - pm) / (x * x - 1.0);
            let step = pn / dp;
            x -= step;
            if step.abs() < 1e-16 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push((0.5 * (1.0 - x), 0.5 * w));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_rules_are_exact_to_degree_2n_minus_1() {
        for n in [1, 2, 3, 5, 8, 12] {
            let rule = gauss_legendre_unit(n);
            for p in 0..(2 * n as i32) {
                let approx: f64 = rule.iter().map(|(s, w)| w * s.powi(p)).sum();
                // ∫₀¹ s^p ds = 1/(p + 1), to rounding
                assert!(
                    (approx - 1.0 / (p + 1) as f64).abs() < 1e-14,
                    "n = {n}, s^{p}: {approx}"
                );
            }
        }
        let three = gauss_legendre_unit(3);
        for ((s, w), (s3, w3)) in three.iter().zip(GAUSS3_UNIT.iter()) {
            assert!((s - s3).abs() < 1e-15 && (w - w3).abs() < 1e-15);
        }
    }

    fn factorial(n: u32) -> f64 {
        (1..=n).map(f64::from).product()
    }

    #[test]
    fn triangle_rules_are_exact_up_to_their_declared_degree() {
        for rule in [TriangleRule::degree4(), TriangleRule::degree6()] {
            let d = rule.degree as u32;
            for p in 0..=d {
                for q in 0..=(d - p) {
                    let exact = factorial(p) * factorial(q) / factorial(p + q + 2);
                    let approx: f64 = rule
                        .iter()
                        .map(|(x, w)| w * x[0].powi(p as i32) * x[1].powi(q as i32))
                        .sum();
                    assert!(
                        (approx - exact).abs() < 1e-14,
                        "degree {d} rule: ξ^{p} η^{q}: {approx} vs {exact}"
                    );
                }
            }
            // and not exact one degree higher (the declaration is tight)
            let p = d + 1;
            let exact = factorial(p) / factorial(p + 2);
            let approx: f64 = rule.iter().map(|(x, w)| w * x[0].powi(p as i32)).sum();
            assert!(
                (approx - exact).abs() > 1e-10,
                "degree {d} rule unexpectedly exact at degree {p}"
            );
        }
    }

    #[test]
    fn gauss3_is_exact_to_degree_five() {
        for p in 0..=5 {
            let approx: f64 = GAUSS3_UNIT.iter().map(|(s, w)| w * s.powi(p)).sum();
            assert!((approx - 1.0 / (p as f64 + 1.0)).abs() < 1e-14, "s^{p}");
        }
    }
}
