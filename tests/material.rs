//! Material level: P and ∂P/∂F against finite differences and automatic differentiation,
//! objectivity, zero energy and stress at rest, +∞ for inverted states.

use pendulum_fem::config::{self, MaterialModel, Plane};
use pendulum_fem::material::{von_mises, Material};

fn materials() -> Vec<Material> {
    let mut out = Vec::new();
    for model in [MaterialModel::NeoHookean, MaterialModel::SaintVenantKirchhoff] {
        for plane in [Plane::Stress, Plane::Strain] {
            let cfg = config::Material {
                model,
                plane,
                youngs_modulus: 2.1e11,
                poisson_ratio: 0.3,
                ..Default::default()
            };
            out.push(Material::from_config(&cfg));
        }
    }
    out
}

/// Deformation gradients with moderate stretch, shear and rotation (row-major vec).
const SAMPLES: [[f64; 4]; 5] = [
    [1.0, 0.0, 0.0, 1.0],
    [1.05, 0.02, -0.01, 0.97],
    [0.9, 0.3, -0.2, 1.1],
    [0.8660254, -0.5, 0.5, 0.8660254], // 30° rotation
    [1.3, -0.1, 0.25, 0.85],
];

#[test]
fn stress_is_the_derivative_of_the_energy() {
    for m in materials() {
        for f in SAMPLES {
            let st = m.stress_tangent(&f);
            for w in 0..4 {
                // central difference with a relative step; error O(h²) ~ 1e-10 relative
                let h = 1e-6;
                let (mut fp, mut fm) = (f, f);
                fp[w] += h;
                fm[w] -= h;
                let fd = (m.energy_density(&fp) - m.energy_density(&fm)) / (2.0 * h);
                let scale = m.mu.max(st.stress[w].abs());
                assert!(
                    (fd - st.stress[w]).abs() < 1e-6 * scale,
                    "{:?} F={f:?} P[{w}] {} vs fd {fd}",
                    m.model,
                    st.stress[w]
                );
            }
        }
    }
}

#[test]
fn tangent_is_the_derivative_of_the_stress() {
    for m in materials() {
        for f in SAMPLES {
            let st = m.stress_tangent(&f);
            for w in 0..4 {
                let h = 1e-7;
                let (mut fp, mut fm) = (f, f);
                fp[w] += h;
                fm[w] -= h;
                let (pp, pm) = (m.stress_tangent(&fp).stress, m.stress_tangent(&fm).stress);
                for v in 0..4 {
                    let fd = (pp[v] - pm[v]) / (2.0 * h);
                    // relative to μ: truncation O(h²·ψ''') and rounding O(ε P / h) both < 1e-6 μ
                    assert!(
                        (fd - st.tangent[v][w]).abs() < 1e-6 * m.mu,
                        "{:?} A[{v}][{w}] {} vs fd {fd}",
                        m.model,
                        st.tangent[v][w]
                    );
                }
            }
        }
    }
}

#[test]
fn closed_form_neo_hookean_matches_automatic_differentiation() {
    for m in materials().into_iter().filter(|m| m.model == MaterialModel::NeoHookean) {
        for f in SAMPLES {
            let (a, b) = (m.stress_tangent(&f), m.stress_tangent_ad(&f));
            assert!((a.energy - b.energy).abs() <= 1e-12 * m.mu);
            for v in 0..4 {
                assert!((a.stress[v] - b.stress[v]).abs() <= 1e-12 * m.mu, "P[{v}]");
                for w in 0..4 {
                    assert!((a.tangent[v][w] - b.tangent[v][w]).abs() <= 1e-11 * m.mu, "A[{v}][{w}]");
                }
            }
        }
    }
}

#[test]
fn energy_and_stress_vanish_at_rest_and_under_rotation() {
    for m in materials() {
        for angle in [0.0f64, 0.3, 1.7, -2.9] {
            let (s, c) = angle.sin_cos();
            let st = m.stress_tangent(&[c, -s, s, c]);
            // a rotation is exact only to rounding: ψ ~ μ ε²-level, P ~ μ ε
            assert!(st.energy.abs() < 1e-4, "{:?} ψ(R({angle})) = {}", m.model, st.energy);
            assert!(
                st.stress.iter().all(|p| p.abs() < 1e-4 * m.mu.sqrt()),
                "{:?} P(R) = {:?}",
                m.model,
                st.stress
            );
        }
    }
}

#[test]
fn energy_is_objective() {
    for m in materials() {
        for f in SAMPLES {
            let psi = m.energy_density(&f);
            for angle in [0.4f64, -1.2, 3.0] {
                let (s, c) = angle.sin_cos();
                // Q F, row-major
                let qf = [
                    c * f[0] - s * f[2],
                    c * f[1] - s * f[3],
                    s * f[0] + c * f[2],
                    s * f[1] + c * f[3],
                ];
                assert!(
                    (m.energy_density(&qf) - psi).abs() <= 1e-9 * psi.abs().max(m.mu * 1e-6),
                    "{:?}",
                    m.model
                );
                // Cauchy stress rotates: σ(QF) = Q σ(F) Qᵀ, so von Mises is invariant
                let (s0, z0) = m.cauchy_stress(&f);
                let (s1, z1) = m.cauchy_stress(&qf);
                assert!((von_mises(s0, z0) - von_mises(s1, z1)).abs() <= 1e-6 * m.mu);
            }
        }
    }
}

#[test]
fn inverted_states_have_infinite_energy() {
    for m in materials() {
        for f in [[1.0, 0.0, 0.0, -0.5], [0.0, 1.0, 1.0, 0.0], [1.0, 2.0, 0.5, 1.0]] {
            assert_eq!(m.energy_density(&f), f64::INFINITY, "{:?} F = {f:?}", m.model);
            assert_eq!(m.stress_tangent(&f).energy, f64::INFINITY);
        }
    }
}

#[test]
fn small_strain_limit_is_linear_plane_stress_elasticity() {
    // Uniaxial stress along x in plane stress: σxx = E εxx, σyy = 0 ⇒ εyy = −ν εxx.
    let cfg = config::Material::default();
    let m = Material::from_config(&cfg);
    let eps = 1e-6;
    let f = [1.0 + eps, 0.0, 0.0, 1.0 - cfg.poisson_ratio * eps];
    let (s, _) = m.cauchy_stress(&f);
    assert!(
        (s[0] / (cfg.youngs_modulus * eps) - 1.0).abs() < 1e-5,
        "σxx/(Eε) = {}",
        s[0] / (cfg.youngs_modulus * eps)
    );
    assert!(s[1].abs() < 1e-5 * s[0].abs(), "σyy = {}", s[1]);
}

#[test]
fn plane_stress_von_mises_is_the_tutorial_formula() {
    let s: [f64; 3] = [3.0e6, -1.0e6, 0.5e6];
    let tutorial = (s[0] * s[0] + s[1] * s[1] - s[0] * s[1] + 3.0 * s[2] * s[2]).sqrt();
    assert!((von_mises(s, 0.0) - tutorial).abs() < 1e-9 * tutorial);
}

#[test]
fn stress_only_path_equals_the_full_evaluation() {
    for m in materials() {
        for f in SAMPLES {
            let (e, p) = m.stress(&f);
            let st = m.stress_tangent(&f);
            assert!((e - st.energy).abs() <= 1e-12 * m.mu);
            for v in 0..4 {
                assert!((p[v] - st.stress[v]).abs() <= 1e-12 * m.mu);
            }
        }
    }
}

#[test]
fn cauchy_stress_is_the_first_piola_stress_pushed_forward() {
    // σ = J⁻¹ P Fᵀ with P from the stress–tangent routine (itself checked against finite
    // differences and automatic differentiation above); the closed form differs by rounding only
    for m in materials() {
        for f in SAMPLES {
            let p = m.stress_tangent(&f).stress;
            let j = f[0] * f[3] - f[1] * f[2];
            let pushed = [
                (p[0] * f[0] + p[1] * f[1]) / j,
                (p[2] * f[2] + p[3] * f[3]) / j,
                (p[0] * f[2] + p[1] * f[3]) / j,
            ];
            let (s, _) = m.cauchy_stress(&f);
            for i in 0..3 {
                assert!(
                    (s[i] - pushed[i]).abs() <= 1e-10 * m.mu,
                    "{:?} F={f:?} σ[{i}] {} vs {}",
                    m.model,
                    s[i],
                    pushed[i]
                );
            }
        }
    }
}

#[test]
fn the_stress_slope_at_rest_is_symmetric_blind_to_rotation_and_plane_stress_hooke() {
    for m in materials() {
        let d = m.stress_slope_at_rest();
        let scale = m.mu;
        // an infinitesimal rotation H = [0, −1, 1, 0] stresses nothing
        for (c, row) in d.iter().enumerate() {
            let s = -row[1] + row[2];
            assert!(s.abs() <= 1e-8 * scale, "component {c}: {s} Pa per unit rotation");
        }
        // the major symmetry of the elasticity tensor: ∂σxx/∂εyy = ∂σyy/∂εxx; shear from either
        // off-diagonal entry alike
        assert!((d[0][3] - d[1][0]).abs() <= 1e-8 * scale, "{:?}", d);
        assert!((d[2][1] - d[2][2]).abs() <= 1e-8 * scale, "{:?}", d);
        // shear modulus: σxy = μ (H₀₁ + H₁₀)
        assert!(
            (d[2][1] - m.mu).abs() <= 1e-8 * scale,
            "σxy slope {} against μ {}",
            d[2][1],
            m.mu
        );
    }
    // plane stress: uniaxial stress σxx = E ε with εyy = −ν ε, nothing else
    let cfg = config::Material::default();
    let d = Material::from_config(&cfg).stress_slope_at_rest();
    let h = [1.0, 0.0, 0.0, -cfg.poisson_ratio];
    let s: Vec<f64> = d
        .iter()
        .map(|row| row.iter().zip(&h).map(|(a, b)| a * b).sum())
        .collect();
    // central differences at 1e-6: truncation 1e-12, rounding ~1e-10 of the slope
    assert!(
        (s[0] / cfg.youngs_modulus - 1.0).abs() < 1e-9,
        "σxx/E = {}",
        s[0] / cfg.youngs_modulus
    );
    for (c, v) in s.iter().enumerate().skip(1) {
        assert!(v.abs() < 1e-9 * cfg.youngs_modulus, "component {c}: {v}");
    }
}
