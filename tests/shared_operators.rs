//! The models of one process share the operators they build from the mesh and the bodies' makeup
//! alone (`simulation::shared`), and only where every input of an operator is the same: a wrong
//! key would hand one model another's mass matrix or loads without a sign. One test in a binary of
//! its own, so that no other test's models evict or forget the operators between its builds.

use crate::common;
use common::Extremes;

use std::sync::Arc;

use pendulum_fem::config::{TorqueProfile, WallKind};
use pendulum_fem::simulation::{forget_shared, Model};
use pendulum_fem::{mesh, Config};

fn model(cfg: &Config) -> Model {
    Model::new(cfg, mesh::generate(cfg).expect("tutorial mesh")).expect("model")
}

/// Whether two models hold the same (shared) pattern, mass matrix, rigid-body functionals,
/// element data, gravity loads and stress recovery, in this order.
fn shared_with(a: &Model, b: &Model) -> [bool; 6] {
    let (pa, pb) = (a.pendulum(), b.pendulum());
    [
        Arc::ptr_eq(&a.pattern, &b.pattern),
        Arc::ptr_eq(&a.mass, &b.mass),
        Arc::ptr_eq(&a.projection, &b.projection),
        Arc::ptr_eq(&pa.elastic.cache, &pb.elastic.cache),
        Arc::ptr_eq(&pa.gravity, &pb.gravity),
        Arc::ptr_eq(&pa.stress, &pb.stress),
    ]
}

#[test]
fn models_share_an_operator_exactly_when_all_its_inputs_agree() {
    let base = Config::default();
    let a = model(&base);

    // the start, the time step and the stiffness change no operator
    let mut same = base.clone();
    same.initial.angle_deg = 55.0;
    same.time.dt = 0.002;
    same.material.youngs_modulus = 7e10;
    assert_eq!(shared_with(&a, &model(&same)), [true; 6]);

    // the density changes the mass matrix and the gravity loads, nothing else
    let mut dense = base.clone();
    dense.material.density = 2700.0;
    let b = model(&dense);
    assert_eq!(shared_with(&a, &b), [true, false, true, true, false, true]);
    let ratio = 2700.0 / 7800.0;
    let largest = a.mass.values.iter().map(|v| v.abs()).max_of();
    for (x, y) in a.mass.values.iter().zip(&b.mass.values) {
        // each entry is ρ t ∫ N_a N_b dA summed over the same points: the ratio of the densities
        // up to the rounding of the sums (1e-15 of the largest entry)
        assert!((y - ratio * x).abs() <= 1e-15 * largest, "{y} against {}", ratio * x);
    }

    // gravity changes its loads only
    let mut moon = base.clone();
    moon.gravity.g = 1.62;
    assert_eq!(shared_with(&a, &model(&moon)), [true, true, true, true, false, true]);

    // the thickness changes the mass, the element data (their weights carry it) and the loads
    let mut thick = base.clone();
    thick.geometry.thickness = 0.02;
    assert_eq!(shared_with(&a, &model(&thick)), [true, false, true, false, false, true]);

    // the rigid wall's contact couples no nodes the elements do not: it changes no operator
    let mut wall = base.clone();
    wall.wall.kind = WallKind::Rigid;
    assert_eq!(shared_with(&a, &model(&wall)), [true; 6]);

    // the torque couples the hinge edge's nodes: a pattern of its own, and the mass matrix lives
    // in it
    let mut torque = base.clone();
    torque.torque.profile = TorqueProfile::Constant;
    torque.torque.amplitude = 0.5;
    assert_eq!(shared_with(&a, &model(&torque)), [false, false, true, true, true, true]);

    // another mesh shares nothing
    let mut fine = base.clone();
    fine.mesh.refine = 1.5;
    assert_eq!(shared_with(&a, &model(&fine)), [false; 6]);

    // and an operator taken from the store is the one a fresh build makes, bit for bit
    forget_shared();
    let fresh = model(&dense);
    assert_eq!(shared_with(&b, &fresh), [false; 6], "forgotten: built again");
    assert_eq!(fresh.mass.values, b.mass.values);
    assert_eq!(fresh.pattern.row_idx, b.pattern.row_idx);
    assert_eq!(
        fresh.pendulum().gravity.load_gradient,
        b.pendulum().gravity.load_gradient
    );
    assert_eq!(fresh.projection.sin_weights, b.projection.sin_weights);
}
