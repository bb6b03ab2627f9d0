//! Constructive geometry: exact integrals, booleans, names and sizes, invalid parameters.

use crate::common;

use std::f64::consts::PI;

use common::{exact, tutorial, with_geometry};
use pendulum_fem::geometry::{self, Curve, Shape};
use pendulum_fem::mesh::generate;
use pendulum_fem::Error;

#[test]
fn pendulum_shape_has_the_reference_area_and_moments_exactly() {
    let cfg = tutorial();
    let shape = geometry::pendulum(&cfg.geometry, &cfg.mesh_sizes()).expect("tutorial geometry");
    let m = shape.moments();
    let d = m.first[0].hypot(m.first[1]) / m.area;
    for (name, value, reference) in [
        ("area", m.area, exact::AREA),
        ("centroid distance", d, exact::CENTROID_DISTANCE),
        ("polar moment / area", m.polar / m.area, exact::POLAR_PER_AREA),
    ] {
        let err = (value - reference).abs() / reference;
        assert!(err < 1e-11, "{name}: {value} vs {reference} (relative {err:.2e})");
    }
    assert!(
        m.first[0].abs() < 1e-15 && m.first[1] < 0.0,
        "the pendulum hangs straight down in −y"
    );
}

/// The reference values (`tests/data/README.md`) against the quadrature of `common::exact`, which
/// integrates the dimensions itself: to the reference's printed digits (13 for the geometry, 9 to
/// 10 for the mass, inertia and frequency).
#[test]
fn the_exact_rigid_values_agree_with_an_independent_quadrature_of_the_tutorial_plate() {
    let cfg = tutorial();
    let (area, first, polar) = exact::plate_moments(&cfg.geometry);
    let rho_t = cfg.material.density * cfg.geometry.thickness;
    let omega = (cfg.gravity.g * (first / area) / (polar / area)).sqrt();
    for (name, value, reference, digits) in [
        ("area", area, exact::AREA, 1e-12),
        ("centroid distance", first / area, exact::CENTROID_DISTANCE, 1e-12),
        ("polar moment / area", polar / area, exact::POLAR_PER_AREA, 1e-12),
        ("mass", rho_t * area, exact::MASS, 1e-9),
        ("inertia", rho_t * polar, exact::INERTIA, 2e-8),
        ("small-amplitude ω", omega, exact::OMEGA_SMALL, 1e-9),
    ] {
        let err = (value - reference).abs() / reference;
        assert!(err < digits, "{name}: {value} vs {reference} (relative {err:.2e})");
    }
}

/// The program's integrals of its curved shape against the independent quadrature, for plates
/// other than the tutorial's (the rod narrower than the hole): to 1e-11 relative, as the tutorial.
#[test]
fn pendulum_shapes_of_other_dimensions_have_the_moments_of_an_independent_quadrature() {
    for (rod, head, hole, distance) in [
        (0.01, 0.05, 0.02, 0.2),
        (0.02, 0.08, 0.05, 0.5),
        (0.005, 0.03, 0.01, 0.04),
    ] {
        let cfg = with_geometry(rod, head, hole, distance);
        let m = geometry::pendulum(&cfg.geometry, &cfg.mesh_sizes()).unwrap().moments();
        let (area, first, polar) = exact::plate_moments(&cfg.geometry);
        for (name, value, reference) in [
            ("area", m.area, area),
            ("first moment", -m.first[1], first),
            ("polar moment", m.polar, polar),
        ] {
            let err = (value - reference).abs() / reference;
            assert!(
                err < 1e-11,
                "{rod}/{head}/{hole}/{distance}: {name} {value} vs {reference} (relative {err:.2e})"
            );
        }
    }
}

#[test]
fn booleans_of_rectangles_and_discs_have_exact_areas() {
    let square = || Shape::rectangle(0.0, 0.0, 2.0, 2.0);
    let cases: [(&str, Shape, f64); 5] = [
        ("square", square(), 4.0),
        ("disc", Shape::circle([1.0, 1.0], 0.5), PI / 4.0),
        (
            "square ∪ half-outside disc",
            square().union(Shape::circle([2.0, 1.0], 1.0)),
            4.0 + PI / 2.0,
        ),
        (
            "square − inner disc",
            square().difference(Shape::circle([1.0, 1.0], 0.5)),
            4.0 - PI / 4.0,
        ),
        (
            "square − corner disc",
            square().difference(Shape::circle([0.0, 0.0], 1.0)),
            4.0 - PI / 4.0,
        ),
    ];
    for (name, shape, area) in cases {
        let a = shape.moments().area;
        assert!((a - area).abs() < 1e-13, "{name}: area {a} vs {area}");
    }
}

#[test]
fn rotation_about_a_point_keeps_the_area_and_turns_the_centroid() {
    let shape = Shape::rectangle(0.0, 0.0, 2.0, 1.0).union(Shape::circle([2.0, 0.5], 0.5));
    let before = shape.moments();
    let after = shape.rotated([0.0, 0.0], PI / 2.0).moments();
    assert!((before.area - after.area).abs() < 1e-14);
    // (x, y) ↦ (−y, x)
    assert!((after.first[0] + before.first[1]).abs() < 1e-13);
    assert!((after.first[1] - before.first[0]).abs() < 1e-13);
    assert!((after.polar - before.polar).abs() < 1e-13);
}

#[test]
fn names_and_sizes_survive_the_booleans() {
    let cfg = tutorial();
    let g = &cfg.geometry;
    let sizes = cfg.mesh_sizes();
    let shape = geometry::pendulum(g, &sizes).expect("tutorial geometry");
    let named = |name: &str| shape.edges.iter().filter(|e| e.name == name).collect::<Vec<_>>();
    let hinge = named(geometry::ROTATION);
    assert_eq!(hinge.len(), 1, "one hinge edge");
    match hinge[0].curve {
        Curve::Line { a, b } => {
            assert!(a[1].abs() < 1e-15 && b[1].abs() < 1e-15, "hinge on y = 0");
            assert!(
                ((a[0] - b[0]).abs() - 2.0 * g.rod_half_width).abs() < 1e-15,
                "hinge is the rod width"
            );
        }
        Curve::Arc { .. } => panic!("the hinge edge is straight"),
    }
    assert_eq!(hinge[0].size, Some(sizes.hinge_edge));
    let head = named(geometry::CONTACT_HEAD);
    assert_eq!(head.len(), 1, "the rod cuts the head circle once");
    match head[0].curve {
        Curve::Arc {
            center, radius, sweep, ..
        } => {
            assert!(center[0].abs() < 1e-15 && (center[1] + g.head_center_distance).abs() < 1e-15);
            assert_eq!(radius, g.head_radius);
            let cut = 2.0 * (g.rod_half_width / g.head_radius).asin();
            assert!((sweep - (2.0 * PI - cut)).abs() < 1e-12, "sweep {sweep}");
        }
        Curve::Line { .. } => panic!("contact_head is a circle"),
    }
    assert_eq!(head[0].size, Some(sizes.circle_edge));
    let default = named(geometry::DEFAULT);
    assert_eq!(default.len(), 3, "two rod sides and the hole");
    let hole: Vec<_> = default
        .iter()
        .filter(|e| matches!(e.curve, Curve::Arc { .. }))
        .collect();
    assert_eq!(hole.len(), 1);
    match hole[0].curve {
        Curve::Arc { sweep, .. } => assert!((sweep + 2.0 * PI).abs() < 1e-12, "the hole runs clockwise"),
        Curve::Line { .. } => unreachable!(),
    }
    assert_eq!(shape.corners.len(), 2);
    for c in &shape.corners {
        assert!((c.point[0].abs() - g.rod_half_width).abs() < 1e-15 && c.point[1].abs() < 1e-15);
        assert_eq!(c.size, sizes.hinge_corner);
    }
    let labels: Vec<(&str, f64)> = shape.regions.iter().map(|r| (r.label.as_str(), r.size)).collect();
    assert_eq!(labels, vec![("head", sizes.head), ("rod", sizes.rod)]);
}

#[test]
fn boundary_is_closed_with_the_domain_on_the_left() {
    let cfg = tutorial();
    let shape = geometry::pendulum(&cfg.geometry, &cfg.mesh_sizes()).expect("tutorial geometry");
    for e in &shape.edges {
        let p = e.curve.point(0.5);
        let d = e.curve.derivative(0.5);
        let n = (d[0].hypot(d[1])).recip();
        let left = [p[0] - 1e-6 * d[1] * n, p[1] + 1e-6 * d[0] * n];
        let right = [p[0] + 1e-6 * d[1] * n, p[1] - 1e-6 * d[0] * n];
        assert!(
            shape.solid.contains(left) && !shape.solid.contains(right),
            "edge {:?}",
            e.name
        );
        let end = e.curve.point(1.0);
        let next_starts = shape.edges.iter().filter(|f| {
            let s = f.curve.point(0.0);
            (s[0] - end[0]).hypot(s[1] - end[1]) < 1e-12
        });
        assert_eq!(next_starts.count(), 1, "every edge end is exactly one edge start");
    }
}

fn geometry_error(cfg: &pendulum_fem::Config) -> String {
    match generate(cfg) {
        Err(Error::Geometry(m)) => m,
        other => panic!("expected a geometry error, got {other:?}"),
    }
}

#[test]
fn every_invalid_geometry_parameter_is_rejected_by_name() {
    let base = tutorial();
    let with = |f: &dyn Fn(&mut pendulum_fem::Config)| {
        let mut c = base.clone();
        f(&mut c);
        c
    };
    let cases: Vec<(&str, pendulum_fem::Config)> = vec![
        ("geometry.rod_half_width", with(&|c| c.geometry.rod_half_width = 0.0)),
        ("geometry.rod_half_width", with(&|c| c.geometry.rod_half_width = 0.07)),
        ("geometry.head_radius", with(&|c| c.geometry.head_radius = -0.06)),
        ("geometry.head_radius", with(&|c| c.geometry.head_radius = f64::NAN)),
        ("geometry.hole_radius", with(&|c| c.geometry.hole_radius = 0.06)),
        ("geometry.hole_radius", with(&|c| c.geometry.hole_radius = -0.01)),
        (
            "geometry.head_center_distance",
            with(&|c| c.geometry.head_center_distance = 0.05),
        ),
        (
            "geometry.head_center_distance",
            with(&|c| c.geometry.head_center_distance = 0.0),
        ),
        ("mesh.max_size", with(&|c| c.mesh.max_size = 0.0)),
        ("mesh.rod_size", with(&|c| c.mesh.rod_size = Some(-1.0))),
        ("mesh.head_size", with(&|c| c.mesh.head_size = Some(0.0))),
        (
            "mesh.hinge_edge_size",
            with(&|c| c.mesh.hinge_edge_size = Some(f64::INFINITY)),
        ),
        (
            "mesh.hinge_corner_size",
            with(&|c| c.mesh.hinge_corner_size = Some(0.0)),
        ),
        (
            "mesh.circle_edge_size",
            with(&|c| c.mesh.circle_edge_size = Some(-0.003)),
        ),
        ("mesh.grading", with(&|c| c.mesh.grading = 0.0)),
    ];
    for (parameter, cfg) in cases {
        let message = geometry_error(&cfg);
        assert!(
            message.contains(parameter),
            "error for {parameter} does not name it: {message}"
        );
    }
}

#[test]
fn an_unknown_mesh_order_is_rejected_by_name() {
    let mut cfg = tutorial();
    cfg.mesh.order = 3;
    match generate(&cfg) {
        Err(Error::Mesh(m)) => assert!(m.contains("mesh.order"), "{m}"),
        other => panic!("expected a mesh error, got {other:?}"),
    }
}

#[test]
fn a_head_that_swallows_the_pivot_is_rejected_even_if_config_validation_is_bypassed() {
    // head_center_distance just below sqrt(R² − r²): the hinge corners would lie inside the head.
    let cfg = with_geometry(0.015, 0.06, 0.03, (0.06f64 * 0.06 - 0.015 * 0.015).sqrt() - 1e-9);
    assert!(geometry_error(&cfg).contains("geometry.head_center_distance"));
}
