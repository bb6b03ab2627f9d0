//! The bare stepper's time for 100 steps of 10 ms of the default pendulum (best of 5 fresh
//! simulations; set-up excluded), the reference for `step_overhead.py`:
//! `cargo run --release -p pendulum-fem-python --example step_overhead`.

use std::time::Instant;

use pendulum_fem_core::{Config, Simulation};

fn main() -> Result<(), pendulum_fem_core::Error> {
    let cfg = Config::default();
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let mut sim = Simulation::build(&cfg)?.simulation;
        let start = Instant::now();
        for _ in 0..100 {
            sim.step(0.01)?;
        }
        best = best.min(start.elapsed().as_secs_f64());
    }
    let per_step = best * 10.0;
    println!("rust: 100 x step(0.01): best {best:.4} s ({per_step:.3} ms per step)");
    Ok(())
}
