//! A model is a list of bodies: a second, separate elastic body with fixed edges changes nothing
//! for the pendulum, stays at rest, and its fixed edges hold.

use crate::common;
use common::Extremes;

use pendulum_fem::config::Material;
use pendulum_fem::simulation::{BodySpec, Model};
use pendulum_fem::terms::Term;
use pendulum_fem::{mesh, Config, Mesh, Simulation};

/// A steel block 0.025 m × 0.25 m whose top edge is named "fix", far to the left of the pendulum
/// (x ∈ [−0.5, −0.475]), 2 × 8 cells.
fn block() -> Mesh {
    let mut m = common::hanging_rectangle(0.0125, 0.25, 2, 8);
    for p in &mut m.nodes {
        p[0] -= 0.4875;
        p[1] -= 0.115;
    }
    // the fixture's names are the pendulum's; the block has its own
    m.boundary_names = vec!["block_side".into(), "fix".into(), "block_unused".into()];
    m.region_name = "block".into();
    m
}

fn spec(gravity: bool) -> BodySpec {
    BodySpec {
        name: "block".into(),
        mesh: block(),
        material: Material::default(),
        thickness: 0.01,
        gravity,
        fixed: vec!["fix".into()],
    }
}

fn pendulum(cfg: &Config, others: &[BodySpec]) -> Simulation {
    let mesh = mesh::generate(cfg).expect("tutorial mesh");
    Simulation::new(Model::with_bodies(cfg, mesh, others).expect("model")).expect("set-up")
}

#[test]
fn a_separate_fixed_block_leaves_the_pendulum_unchanged_and_stays_at_rest_with_zero_energy() {
    let cfg = Config::default();
    let mut alone = pendulum(&cfg, &[]);
    // gravity off on the block: unloaded, it must not move at all
    let mut two = pendulum(&cfg, &[spec(false)]);
    let block_nodes = two.model.bodies[1].nodes.clone();
    let np = alone.model.mesh.num_nodes();
    assert_eq!(two.model.bodies[0].nodes, 0..np, "the pendulum's nodes come first");
    for step in 1..=100 {
        let its_alone = alone.step(0.01).unwrap();
        let its_two = two.step(0.01).unwrap();
        // the block adds no residual, so Newton takes the same path; only the factorisation of the
        // larger (block-diagonal) matrix may round differently: 1e-12 rad is ~1e4 ε of θ
        assert_eq!(its_two, its_alone, "step {step}: Newton iterations");
        assert!(
            (two.theta() - alone.theta()).abs() <= 1e-12,
            "step {step}: θ {} vs {}",
            two.theta(),
            alone.theta()
        );
        let (a, b) = (alone.energies(), two.energies());
        assert!(
            (a.total - b.total).abs() <= 1e-12 * a.kinetic.max(1e-3),
            "step {step}: total energy {} vs {}",
            b.total,
            a.total
        );
    }
    // the block: exactly at rest, undeformed, no energy
    let u = two.displacement();
    let v = two.velocity();
    assert!(block_nodes.clone().all(|n| u[2 * n] == 0.0 && u[2 * n + 1] == 0.0));
    assert!(block_nodes.clone().all(|n| v[2 * n] == 0.0 && v[2 * n + 1] == 0.0));
    let cx = two.context();
    let block = &two.model.bodies[1];
    assert_eq!(block.elastic.energy(u, &cx), 0.0);
    assert_eq!(block.gravity.energy(u, &cx), 0.0);
    // the pendulum's displacement itself agrees to the same rounding level
    let ua = alone.displacement();
    let worst = (0..2 * np).map(|i| (u[i] - ua[i]).abs()).max_of();
    assert!(worst < 1e-12, "largest displacement difference {worst:e} m");
}

#[test]
fn a_fixed_edge_holds_while_the_block_hangs_under_its_own_weight() {
    let cfg = Config::default();
    let mut two = pendulum(&cfg, &[spec(true)]);
    let body = &two.model.bodies[1];
    let fixed = body.fixed_dofs.clone();
    let nodes = body.nodes.clone();
    assert_eq!(
        fixed.len(),
        2 * 5,
        "2 cells of the top edge: 5 nodes, 2 components each"
    );
    for _ in 0..20 {
        two.step(0.01).unwrap();
    }
    let u = two.displacement();
    assert!(fixed.iter().all(|&d| u[d] == 0.0), "fixed degrees of freedom moved");
    // the initial equilibrium hangs the block in its static sag, which it keeps: a bar under its
    // own weight lengthens at the free end by ρ g L² / (2E) (uniaxial stress; the fixed edge's
    // restraint of the lateral contraction changes that by well under the 5 % allowed)
    let (rho, e, l) = (7800.0, 2.1e11, 0.25);
    let expected = rho * 9.81 * l * l / (2.0 * e);
    let sag = nodes.clone().map(|n| -u[2 * n + 1]).max_of();
    assert!(
        (sag - expected).abs() < 0.05 * expected,
        "sag {sag:e} m vs ρgL²/2E = {expected:e} m"
    );
    // and it stays there: the block's velocities are rounding-level (1e-9 of sag per step)
    let v = two.velocity();
    let fastest = nodes.map(|n| v[2 * n].hypot(v[2 * n + 1])).max_of();
    assert!(fastest < 1e-6 * expected / 0.01, "block speed {fastest:e} m/s");
}
