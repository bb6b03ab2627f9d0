//! The generated mesh: conformity, names, quality, Jacobians, exactness and its rate.

use crate::common;

use common::{assert_conforming, chord, tutorial, with_geometry};
use pendulum_fem::geometry;
use pendulum_fem::mesh::bench::scaled_config;
use pendulum_fem::mesh::{generate, generate_with_stats};
use pendulum_fem::{Config, Mesh};
use proptest::prelude::*;

const AREA: f64 = 1.390122999328e-02;
const CENTROID_DISTANCE: f64 = 1.816508466954e-01;
const POLAR_PER_AREA: f64 = 4.078850906421e-02;

fn tutorial_mesh() -> Mesh {
    generate(&tutorial()).expect("the tutorial mesh is generated")
}

#[test]
fn tutorial_mesh_is_conforming_with_one_hole() {
    let mesh = tutorial_mesh();
    assert_eq!(assert_conforming(&mesh), 0, "V − E + F = 1 − 1 for one hole");
}

#[test]
fn mesh_without_hole_is_conforming_and_simply_connected() {
    let mut cfg = tutorial();
    cfg.geometry.hole_radius = 0.0;
    let mesh = generate(&cfg).expect("mesh without hole");
    assert_eq!(assert_conforming(&mesh), 1, "V − E + F = 1 without hole");
}

#[test]
fn tutorial_mesh_has_a_netgen_like_triangle_count() {
    let mesh = tutorial_mesh();
    let n = mesh.triangles.len();
    assert!((900..=2000).contains(&n), "{n} triangles (Netgen: 1180)");
}

#[test]
fn tutorial_mesh_has_minimum_angle_of_at_least_25_degrees() {
    let angle = tutorial_mesh().min_angle_deg();
    assert!(angle >= 25.0, "minimum angle {angle:.2}°");
}

#[test]
fn every_curved_element_has_a_positive_jacobian_without_straightening() {
    let (mesh, stats) = generate_with_stats(&tutorial()).expect("mesh");
    assert_eq!(stats.straightened, 0, "no curved edge had to be straightened");
    for t in 0..mesh.triangles.len() {
        let det = mesh.min_jacobian(t);
        assert!(det > 0.0, "element {t}: det J = {det:e}");
    }
}

#[test]
fn hinge_edges_lie_on_y_zero_within_the_rod_and_cover_its_width() {
    let cfg = tutorial();
    let r = cfg.geometry.rod_half_width;
    let mesh = tutorial_mesh();
    let mut length = 0.0;
    for e in mesh.edges_named(geometry::ROTATION) {
        for &n in &e.nodes {
            let [x, y] = mesh.nodes[n];
            assert!(y == 0.0 && x.abs() <= r, "hinge node ({x}, {y})");
        }
        length += chord(&mesh, e.nodes);
    }
    assert!((length - 2.0 * r).abs() < 1e-14, "hinge length {length} vs {}", 2.0 * r);
    let nodes = mesh.nodes_on(geometry::ROTATION);
    let count = mesh.edges_named(geometry::ROTATION).count();
    assert_eq!(
        nodes.len(),
        2 * count + 1,
        "a chain of {count} quadratic edges has 2n + 1 nodes"
    );
    // Hinge edges are about hinge_edge_size long, finer at the corners.
    let h = cfg.mesh_sizes().hinge_edge;
    for e in mesh.edges_named(geometry::ROTATION) {
        assert!(
            chord(&mesh, e.nodes) <= 1.5 * h,
            "hinge edge longer than 1.5 × hinge_edge_size"
        );
    }
}

#[test]
fn contact_head_edges_lie_on_the_head_circle_and_miss_only_the_rod_cut() {
    let g = tutorial().geometry;
    let (r, big_r, l) = (g.rod_half_width, g.head_radius, g.head_center_distance);
    let mesh = tutorial_mesh();
    let mut length = 0.0;
    for e in mesh.edges_named(geometry::CONTACT_HEAD) {
        for &n in &e.nodes {
            let [x, y] = mesh.nodes[n];
            let rho = x.hypot(y + l);
            assert!((rho - big_r).abs() < 1e-15, "node at radius {rho}, head radius {big_r}");
        }
        length += chord(&mesh, e.nodes);
    }
    let expected = 2.0 * std::f64::consts::PI * big_r - 2.0 * big_r * (r / big_r).asin();
    assert!(
        (length - expected).abs() < 1e-3 * expected,
        "contact_head length {length} vs {expected}"
    );
    let default_on_hole = mesh
        .edges_named(geometry::DEFAULT)
        .filter(|e| {
            e.nodes.iter().all(|&n| {
                let [x, y] = mesh.nodes[n];
                (x.hypot(y + l) - g.hole_radius).abs() < 1e-15
            })
        })
        .count();
    assert!(
        default_on_hole >= 20,
        "the hole circle is a 'default' boundary on the exact circle"
    );
}

#[test]
fn straight_mesh_has_midpoint_mid_nodes() {
    let mut cfg = tutorial();
    cfg.mesh.order = 1;
    let mesh = generate(&cfg).expect("order-1 mesh");
    assert_eq!(mesh.order, 1);
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b, m) = (mesh.nodes[t[k]], mesh.nodes[t[(k + 1) % 3]], mesh.nodes[t[3 + k]]);
            assert!((m[0] - 0.5 * (a[0] + b[0])).abs() < 1e-16 && (m[1] - 0.5 * (a[1] + b[1])).abs() < 1e-16);
        }
    }
}

fn relative_errors(mesh: &Mesh) -> [f64; 3] {
    let area = mesh.area();
    let s = mesh.first_moment();
    let d = s[0].hypot(s[1]) / area;
    let ip = mesh.polar_moment() / area;
    [
        (area - AREA).abs() / AREA,
        (d - CENTROID_DISTANCE).abs() / CENTROID_DISTANCE,
        (ip - POLAR_PER_AREA).abs() / POLAR_PER_AREA,
    ]
}

#[test]
fn curved_tutorial_mesh_reproduces_area_centroid_distance_and_polar_moment() {
    let mesh = tutorial_mesh();
    eprintln!("relative errors (area, d, I_p/A): {:?}", relative_errors(&mesh));
    for (name, err) in ["area", "pivot-centroid distance", "polar moment / area"]
        .iter()
        .zip(relative_errors(&mesh))
    {
        assert!(err < 5e-7, "{name}: relative error {err:.3e}");
    }
    let s = mesh.first_moment();
    assert!(
        s[0].abs() < 1e-12 && s[1] < 0.0,
        "centroid straight below the pivot: {s:?}"
    );
}

/// Relative errors of the area and of the polar moment `∫ |x|² dA` about the pivot.
fn area_and_polar_errors(cfg: &Config) -> [f64; 2] {
    let mesh = generate(cfg).expect("mesh");
    let polar = POLAR_PER_AREA * AREA;
    [
        (mesh.area() - AREA).abs() / AREA,
        (mesh.polar_moment() - polar).abs() / polar,
    ]
}

#[test]
fn area_and_polar_moment_errors_converge_at_fourth_order_when_curved_and_second_order_when_straight() {
    // Expected orders: P2 boundary interpolation O(h⁴), straight chords O(h²).
    for (order, min_rate, max_rate) in [(2u32, 3.0, 6.0), (1, 1.8, 2.5)] {
        let errors: Vec<[f64; 2]> = [1.0, 0.5, 0.25]
            .iter()
            .map(|&f| {
                let mut cfg = scaled_config(&tutorial(), f);
                cfg.mesh.order = order;
                area_and_polar_errors(&cfg)
            })
            .collect();
        eprintln!("order {order}: relative (area, polar moment) errors {errors:?}");
        // Straight chords lose polar moment on the head circle and gain it on the hole, so only the
        // area shows a clean order-1 rate.
        let quantities: &[&str] = if order == 2 {
            &["area", "polar moment"]
        } else {
            &["area"]
        };
        for (q, quantity) in quantities.iter().enumerate() {
            for w in errors.windows(2) {
                let rate = (w[0][q] / w[1][q]).log2();
                assert!(
                    rate > min_rate && rate < max_rate,
                    "order {order}, {quantity}: errors {errors:?}, rate {rate:.2}"
                );
            }
        }
    }
}

#[test]
fn benchmark_reports_the_tutorial_mesh() {
    let results = pendulum_fem::mesh::bench::bench_mesh(&tutorial(), None).expect("benchmark runs");
    assert_eq!(results.len(), 1);
    assert_eq!(results[0].triangles, tutorial_mesh().triangles.len());
    assert!(results[0].seconds > 0.0);
}

#[test]
fn mesh_generation_is_deterministic() {
    assert_eq!(tutorial_mesh(), tutorial_mesh());
}

#[test]
fn mesh_sizes_follow_the_configuration() {
    // Halving every size multiplies the count by 2 to 4: the graded part (h_s + g·dist) does not halve.
    let coarse = generate(&tutorial()).expect("mesh").triangles.len() as f64;
    let fine = generate(&scaled_config(&tutorial(), 0.5))
        .expect("mesh")
        .triangles
        .len() as f64;
    let ratio = fine / coarse;
    assert!((2.0..4.5).contains(&ratio), "count ratio {ratio:.2}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn random_valid_pendulums_mesh_conformingly_with_quality_and_exact_area(
        head in 0.03f64..0.1,
        rod_fraction in 0.1f64..0.6,
        hole_fraction in 0.0f64..0.8,
        distance_factor in 1.2f64..5.0,
        grading in 0.15f64..0.6,
        order in 1u32..=2,
    ) {
        let hole = if hole_fraction < 0.1 { 0.0 } else { hole_fraction * head };
        let mut cfg = with_geometry(rod_fraction * head, head, hole, distance_factor * head);
        cfg.mesh.grading = grading;
        cfg.mesh.order = order;
        cfg.mesh.max_size = head / 2.0;
        let mesh = generate(&cfg).expect("valid geometry meshes");
        let euler = assert_conforming(&mesh);
        prop_assert_eq!(euler, if hole > 0.0 { 0 } else { 1 });
        let angle = mesh.min_angle_deg();
        prop_assert!(angle >= 25.0, "minimum angle {:.2}", angle);
        for t in 0..mesh.triangles.len() {
            prop_assert!(mesh.min_jacobian(t) > 0.0, "element {} inverted", t);
        }
        let exact = geometry::pendulum(&cfg.geometry, &cfg.mesh_sizes()).expect("shape").moments().area;
        // the curved (quadratic) edges approximate each circle with an area error that grows like
        // (h/R)^4 of the smallest circle: a 3 mm hole in a 30 mm head at grading 0.15 reaches 1.2e-6
        // (saved in mesh.proptest-regressions); straight edges lose the circular segments
        let tol = if order == 2 { 5e-6 } else { 2e-3 };
        let err = (mesh.area() - exact).abs() / exact;
        prop_assert!(err < tol, "area error {:.3e}", err);
        let hinge: f64 = mesh.edges_named(geometry::ROTATION).map(|e| chord(&mesh, e.nodes)).sum();
        prop_assert!((hinge - 2.0 * cfg.geometry.rod_half_width).abs() < 1e-12);
    }
}
