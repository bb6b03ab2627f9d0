//! The bare stepper's real-time factor for the FMU's default pendulum (20°, the torque input
//! declared), at steps of 10 ms and 1 ms: the reference for the FMU's overhead
//! (`examples/fmpy_speed.py` drives the FMU the same way through fmpy).
//!
//! `cargo run --release -p pendulum-fem-fmu --example stepper_speed [SIMULATED_SECONDS]`

use std::time::Instant;

use pendulum_fem::{mesh, Config, Simulation};

fn main() {
    let seconds: f64 = std::env::args().nth(1).map_or(2.0, |s| s.parse().expect("seconds"));
    let sets = ["torque.profile=\"constant\"".to_string(), "torque.amplitude=0.0".into()];
    let cfg = Config::load(None, &sets).expect("config");
    for dt in [0.01, 0.001] {
        let mut sim = Simulation::from_config(&cfg, mesh::generate(&cfg).expect("mesh")).expect("model");
        let steps = (seconds / dt).round() as usize;
        let start = Instant::now();
        let mut sum = 0.0;
        for _ in 0..steps {
            sim.step(dt).expect("step");
            sum += sim.theta();
        }
        let wall = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let (omega, alpha) = sim.angular_rates();
        let energy = sim.energies().total;
        let outputs = start.elapsed().as_secs_f64();
        println!(
            "bare stepper dt = {dt} s: {steps} steps in {wall:.3} s, real-time factor {:.2} \
             ({:.3} ms/step; one read of omega, alpha, energy {:.3} ms) [{sum:.3} {omega:.3} {alpha:.3} {energy:.3}]",
            seconds / wall,
            1e3 * wall / steps as f64,
            1e3 * outputs
        );
    }
}
