//! Mesh options a user reaches for: `mesh.refine` refines the whole mesh, and a `mesh.max_size`
//! that bounds no element is reported instead of silently ignored.

use pendulum_fem::mesh::{generate, max_size_warning};
use pendulum_fem::Config;

fn with(sets: &[&str]) -> Config {
    Config::load(None, &sets.iter().map(|s| s.to_string()).collect::<Vec<_>>()).unwrap()
}

#[test]
fn refine_two_refines_the_whole_mesh_and_keeps_its_area() {
    let base = generate(&Config::default()).unwrap();
    let fine = generate(&with(&["mesh.refine=2"])).unwrap();
    // halving every size: 1233 → 3436 triangles (not 4×: the grading zone around the small
    // features shrinks with the sizes)
    let ratio = fine.triangles.len() as f64 / base.triangles.len() as f64;
    assert!(
        ratio > 2.5,
        "{} → {} triangles",
        base.triangles.len(),
        fine.triangles.len()
    );
    for name in ["rotation", "contact_head"] {
        let (a, b) = (base.edges_named(name).count(), fine.edges_named(name).count());
        assert!(b as f64 >= 1.8 * a as f64, "{name}: {a} → {b} edges");
    }
    // curved P2 geometry: the area error is O(h⁴), 3e-8 relative at the default size
    let rel = (fine.area() - base.area()).abs() / base.area();
    assert!(rel < 1e-7, "area changes by {rel:e}");
}

#[test]
fn a_max_size_that_bounds_no_element_is_warned_about_naming_refine() {
    let cfg = with(&["mesh.max_size=0.01"]);
    let mesh = generate(&cfg).unwrap();
    assert_eq!(
        mesh,
        generate(&Config::default()).unwrap(),
        "the same mesh as the default"
    );
    let w = max_size_warning(&cfg, &mesh).expect("a warning");
    assert!(w.contains("mesh.max_size = 0.01") && w.contains("mesh.refine"), "{w}");

    let cfg = with(&["mesh.max_size=0.005"]);
    let mesh = generate(&cfg).unwrap();
    assert!(mesh.triangles.len() > 1233, "0.005 m bounds the head elements");
    assert_eq!(max_size_warning(&cfg, &mesh), None);

    let cfg = Config::default();
    assert_eq!(
        max_size_warning(&cfg, &generate(&cfg).unwrap()),
        None,
        "no warning for the default"
    );
}
