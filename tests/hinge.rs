//! The hinge on a small structured pendulum: hanging at rest it carries the weight and does not
//! turn; swinging it keeps the hinge edge's mean displacement at zero, and Newton converges in
//! few iterations.

use crate::common;

use pendulum_fem::simulation::Simulation;
use pendulum_fem::Config;

fn config(angle_deg: f64) -> Config {
    let mut cfg = Config::default();
    cfg.initial.angle_deg = angle_deg;
    cfg.time.end = 0.2;
    cfg
}

#[test]
fn hanging_at_rest_the_reaction_equals_the_weight() {
    let mesh = common::hanging_rectangle(0.015, 0.3, 2, 10);
    let cfg = config(0.0);
    let mut sim = Simulation::from_config(&cfg, mesh).unwrap();
    // the rectangle's weight, ρ t (2w) l g (straight edges: the mesh's area is exact)
    let weight = cfg.material.density * cfg.geometry.thickness * (2.0 * 0.015) * 0.3 * cfg.gravity.g;
    for _ in 0..20 {
        let r = sim.advance().unwrap();
        assert!(
            (r.hinge_force[1] / weight - 1.0).abs() < 1e-6,
            "reaction {} vs weight {weight}",
            r.hinge_force[1]
        );
        assert!(r.hinge_force[0].abs() < 1e-6 * weight);
        assert!(r.theta.abs() < 1e-10, "theta {}", r.theta);
    }
}

#[test]
fn swinging_keeps_the_hinge_and_converges_in_few_iterations() {
    let mesh = common::hanging_rectangle(0.015, 0.3, 2, 10);
    let mut sim = Simulation::from_config(&config(30.0), mesh).unwrap();
    let e0 = sim.record(0).total;
    let mut kin_max = 0.0f64;
    for _ in 0..20 {
        let r = sim.advance().unwrap();
        assert!(
            r.newton_iterations <= 3,
            "Newton took {} iterations",
            r.newton_iterations
        );
        let c = sim.model.hinge.value(sim.displacement());
        assert!(
            c[0].abs() < 1e-12 && c[1].abs() < 1e-12,
            "hinge mean displacement {c:?}"
        );
        kin_max = kin_max.max(r.kinetic);
        assert!(
            (r.total - e0).abs() < 1e-3 * kin_max.max(1e-3),
            "energy drift {}",
            r.total - e0
        );
    }
}
