//! Cost of the actuator torque: 100 steps of the default pendulum without and with a follower
//! torque (best of five, set-up excluded), once with 0.1 N m and once with 0 N m (same motion as
//! without torque, so the pure cost of the term and its denser pattern).
//!
//! `cargo run --release --example bench_torque [steps] [repeats]`
fn main() -> Result<(), pendulum_fem::Error> {
    let mut args = std::env::args().skip(1);
    let steps = args.next().and_then(|a| a.parse().ok()).unwrap_or(100);
    let repeats = args.next().and_then(|a| a.parse().ok()).unwrap_or(5);
    let cfg = pendulum_fem::Config::default();
    for amplitude in [0.1, 0.0] {
        pendulum_fem::commands::bench::bench_torque(&cfg, steps, repeats, amplitude)?;
    }
    Ok(())
}
