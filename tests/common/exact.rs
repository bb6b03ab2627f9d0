//! The exact rigid pendulum of the tutorial (rod ∪ head disc − hole, `tests/data/README.md`): the
//! reference values, and the same quantities integrated here from a configuration's dimensions,
//! independently of the program's mesh and quadrature.

use pendulum_fem::config::Geometry;

/// Area \[m²\] of the tutorial's pendulum (exact integration over the curved region).
pub const AREA: f64 = 1.390122999328e-2;
/// Distance from the pivot to the centroid \[m\].
pub const CENTROID_DISTANCE: f64 = 1.816508466954e-1;
/// Mass \[kg\] at ρ = 7800 kg/m³ and a thickness of 0.01 m.
pub const MASS: f64 = 1.084295939;
/// Polar moment about the pivot per area, `I_p/A` \[m²\].
pub const POLAR_PER_AREA: f64 = 4.078850906421e-2;
/// Moment of inertia about the pivot \[kg m²\], at the same density and thickness.
pub const INERTIA: f64 = 0.044226815;
/// Small-amplitude angular frequency `√(g d / (I_p/A))` at g = 9.81 \[rad/s\].
pub const OMEGA_SMALL: f64 = 6.609738859;
/// The period of the swing released from rest at 20° (`4 K(sin²(θ₀/2)) / ω`) \[s\].
pub const PERIOD_20_DEG: f64 = 0.957885229;

/// Area, first moment `∫ −y dA` and polar moment `∫ (x² + y²) dA` about the pivot of the plate of
/// `g` (per unit thickness; \[m²\], \[m³\], \[m⁴\]).
///
/// The plate is the annulus `r_hole ≤ ρ ≤ R` about the head's centre, at distance `l` below the
/// pivot, plus the part of the rod `|x| ≤ w` that lies above the head disc, `0 ≤ −y ≤ l − √(R² −
/// x²)` (the hole is wider than the rod, so no rod is left inside it). The annulus is exact; the
/// rod's column integrals are exact in y and summed over x by 64-point Gauss–Legendre rules on 16
/// panels (the integrand is smooth since `w < R`), to rounding.
pub fn plate_moments(g: &Geometry) -> (f64, f64, f64) {
    let (w, big_r, r_hole, l) = (g.rod_half_width, g.head_radius, g.hole_radius, g.head_center_distance);
    assert!(
        r_hole >= w && w < big_r,
        "plate_moments: the rod must be narrower than the hole and the head"
    );
    let pi = std::f64::consts::PI;
    let ring_area = pi * (big_r * big_r - r_hole * r_hole);
    let ring_first = ring_area * l;
    let ring_polar = 0.5 * pi * (big_r.powi(4) - r_hole.powi(4)) + ring_area * l * l;
    // the rod's column at x reaches from the pivot down to depth h(x), where it meets the disc
    let column = |x: f64| {
        let h = l - (big_r * big_r - x * x).sqrt();
        (h, 0.5 * h * h, x * x * h + h * h * h / 3.0)
    };
    let (mut area, mut first, mut polar) = (0.0, 0.0, 0.0);
    let panels = 16;
    let (nodes, weights) = gauss_legendre(64);
    for p in 0..panels {
        let (a, b) = (
            -w + 2.0 * w * p as f64 / panels as f64,
            -w + 2.0 * w * (p + 1) as f64 / panels as f64,
        );
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        for (t, wt) in nodes.iter().zip(&weights) {
            let (h, f, q) = column(mid + half * t);
            area += half * wt * h;
            first += half * wt * f;
            polar += half * wt * q;
        }
    }
    (ring_area + area, ring_first + first, ring_polar + polar)
}

/// The nodes and weights of the `n`-point Gauss–Legendre rule on `[−1, 1]` (Newton's method on
/// the Legendre polynomial from the Chebyshev-like first guesses, to rounding).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut nodes, mut weights) = (vec![0.0; n], vec![0.0; n]);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut derivative = 0.0;
        for _ in 0..100 {
            // P_n(x) and P_n'(x) by the three-term recurrence
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                (p0, p1) = (p1, p2);
            }
            derivative = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / derivative;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        nodes[i] = x;
        weights[i] = 2.0 / ((1.0 - x * x) * derivative * derivative);
    }
    (nodes, weights)
}
