//! Newmark as an incremental potential: second order on a linear oscillator, and the presets.

use pendulum_fem::model::State;
use pendulum_fem::scheme::Newmark;

/// Integrates m ü + k u = 0 (m = 1) from u = 1, v = 0 to `t_end` with `steps` steps of `scheme`
/// with HHT weight `alpha` (0: plain Newmark), minimising the scalar incremental potential
/// c/2 (u − ũ)² + (1 + α) k/2 u² − α k uₙ u exactly.
fn integrate(scheme: Newmark, alpha: f64, k: f64, t_end: f64, steps: usize) -> State {
    let dt = t_end / steps as f64;
    let mut s = State {
        t: 0.0,
        u: vec![1.0],
        v: vec![0.0],
        a: vec![-k],
    };
    for _ in 0..steps {
        let pred = scheme.predict_u(dt, &s)[0];
        let c = scheme.inertia_factor(dt);
        let u_new = (c * pred + alpha * k * s.u[0]) / (c + (1.0 + alpha) * k);
        s = scheme.correct(dt, &s, vec![u_new]);
    }
    s
}

#[test]
fn newmark_variants_are_second_order() {
    for scheme in [Newmark::AVERAGE_ACCELERATION, Newmark::LINEAR_ACCELERATION] {
        let exact = (2.0f64 * 2.0).cos();
        let error = |steps| (integrate(scheme, 0.0, 4.0, 2.0, steps).u[0] - exact).abs();
        let rate = (error(64) / error(128)).log2();
        assert!(rate > 1.9, "{scheme:?}: observed order {rate:.2}");
    }
}

#[test]
fn average_acceleration_is_the_tutorial_update() {
    // v⁺ = 2/Δt (u⁺ − u) − v,  a⁺ = 2/Δt (v⁺ − v) − a
    let s = State {
        t: 0.0,
        u: vec![0.3, -0.1],
        v: vec![1.0, 2.0],
        a: vec![-3.0, 0.5],
    };
    let dt = 0.01;
    let u_new = vec![0.31, -0.08];
    let n = Newmark::AVERAGE_ACCELERATION.correct(dt, &s, u_new.clone());
    for i in 0..2 {
        let v = 2.0 / dt * (u_new[i] - s.u[i]) - s.v[i];
        let a = 2.0 / dt * (v - s.v[i]) - s.a[i];
        assert!((n.v[i] - v).abs() < 1e-9 && (n.a[i] - a).abs() < 1e-6, "component {i}");
    }
}

#[test]
fn average_acceleration_conserves_the_energy_of_a_linear_oscillator() {
    let s = integrate(Newmark::AVERAGE_ACCELERATION, 0.0, 4.0, 50.0, 1000);
    let e = 0.5 * s.v[0] * s.v[0] + 0.5 * 4.0 * s.u[0] * s.u[0];
    assert!((e - 2.0).abs() < 1e-12, "energy {e}");
}

#[test]
fn hht_is_second_order_and_damps_unresolved_modes() {
    let alpha = -0.05;
    let exact = (2.0f64 * 2.0).cos();
    let error = |steps| (integrate(Newmark::hht(alpha), alpha, 4.0, 2.0, steps).u[0] - exact).abs();
    let rate = (error(64) / error(128)).log2();
    assert!(rate > 1.9, "observed order {rate:.2}");
    // ω Δt = 1000: the amplitude shrinks by the spectral radius (1 + α)/(1 − α) per step
    let k = 1e6;
    let s = integrate(Newmark::hht(alpha), alpha, k, 1.0, 20); // dt = 0.05, ω dt = 50
    let energy = 0.5 * s.v[0] * s.v[0] + 0.5 * k * s.u[0] * s.u[0];
    let rho: f64 = (1.0 + alpha) / (1.0 - alpha);
    assert!(energy < 0.5 * k * rho.powi(20) * 1.5, "energy {energy} not damped");
}

#[test]
fn hht_with_zero_alpha_is_the_average_acceleration_rule() {
    assert_eq!(Newmark::hht(0.0), Newmark::AVERAGE_ACCELERATION);
}
