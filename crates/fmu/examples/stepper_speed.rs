//! The bare stepper's real-time factor for the FMU's default pendulum (20°, the torque input
//! declared), at steps of 10 ms and 1 ms, stepping only and stepping with every FMU output read
//! after each step: the reference for the FMU's overhead (`examples/fmpy_speed.py` drives the FMU
//! the same way through fmpy). Best of `REPEATS` runs, wall and CPU time (all threads).
//!
//! `cargo run --release -p pendulum-fem-fmu --example stepper_speed [SIMULATED_SECONDS [REPEATS]]`

use std::time::Instant;

use pendulum_fem_core::{Config, Simulation};
use pendulum_fem_fmu::contact::contact_outputs;

/// CPU time of this process (user + system, all threads) \[s\], from `/proc/self/stat`.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat.rsplit(')').next().unwrap_or("").split_whitespace().collect();
    let ticks = |i: usize| fields.get(i).and_then(|f| f.parse::<f64>().ok()).unwrap_or(f64::NAN);
    // after the command name: state is field 0, utime field 11, stime field 12 (clock ticks of 1/100 s)
    (ticks(11) + ticks(12)) / 100.0
}

fn main() {
    let mut args = std::env::args().skip(1);
    let seconds: f64 = args.next().map_or(2.0, |s| s.parse().expect("seconds"));
    let repeats: usize = args.next().map_or(3, |s| s.parse().expect("repeats"));
    let sets = ["torque.profile=\"constant\"".to_string(), "torque.amplitude=0.0".into()];
    let cfg = Config::load(None, &sets).expect("config");
    for dt in [0.01, 0.001] {
        for read_outputs in [false, true] {
            let (mut best_wall, mut best_cpu) = (f64::INFINITY, f64::INFINITY);
            let steps = (seconds / dt).round() as usize;
            for _ in 0..repeats {
                let mut sim = Simulation::build(&cfg).expect("model").simulation;
                let (start, cpu) = (Instant::now(), cpu_seconds());
                let mut sum = 0.0;
                for _ in 0..steps {
                    sim.step(dt).expect("step");
                    sum += sim.theta();
                    if read_outputs {
                        let (omega, alpha) = sim.angular_rates();
                        sum += omega + alpha + sim.energies().total + contact_outputs(&sim, false).gap;
                    }
                }
                best_wall = best_wall.min(start.elapsed().as_secs_f64());
                best_cpu = best_cpu.min(cpu_seconds() - cpu);
                std::hint::black_box(sum);
            }
            println!(
                "bare stepper dt = {dt} s, {}: {steps} steps, best of {repeats}: wall {best_wall:.3} s \
                 (real-time factor {:.2}, {:.3} ms/step), CPU {best_cpu:.2} s",
                if read_outputs {
                    "every output read"
                } else {
                    "stepping only"
                },
                seconds / best_wall,
                1e3 * best_wall / steps as f64,
            );
        }
    }
}
