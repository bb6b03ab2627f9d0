//! Stress run over random valid pendulums (not part of the suite): prints any failure.
//!
//! `cargo run --release --example stress_mesh [cases]`
use pendulum_fem::{geometry, mesh::generate, Config};

fn main() {
    let cases: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(200);
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut worst_angle = f64::INFINITY;
    let mut failures = 0;
    for case in 0..cases {
        let head = 0.02 + 0.1 * rnd();
        let mut cfg = Config::default();
        cfg.geometry.head_radius = head;
        cfg.geometry.rod_half_width = head * (0.05 + 0.9 * rnd());
        let hole = rnd();
        cfg.geometry.hole_radius = if hole < 0.15 { 0.0 } else { head * 0.95 * hole };
        let reach = (head * head - cfg.geometry.rod_half_width.powi(2)).sqrt();
        cfg.geometry.head_center_distance = reach * (1.01 + 5.0 * rnd());
        cfg.mesh.grading = 0.05 + 0.95 * rnd();
        cfg.mesh.max_size = head * (0.1 + 2.0 * rnd());
        let s = cfg.mesh_sizes();
        cfg.mesh.circle_edge_size = Some(s.circle_edge * (0.3 + 3.0 * rnd()));
        cfg.mesh.hinge_corner_size = Some(s.hinge_corner * (0.1 + 3.0 * rnd()));
        cfg.mesh.hinge_edge_size = Some(s.hinge_edge * (0.1 + 3.0 * rnd()));
        cfg.mesh.rod_size = Some(s.rod * (0.2 + 3.0 * rnd()));
        cfg.mesh.head_size = Some(s.head * (0.2 + 3.0 * rnd()));
        cfg.mesh.order = if rnd() < 0.5 { 1 } else { 2 };
        let result = generate(&cfg);
        match result {
            Ok(mesh) => {
                let angle = mesh.min_angle_deg();
                worst_angle = worst_angle.min(angle);
                let exact = geometry::pendulum(&cfg.geometry, &cfg.mesh_sizes())
                    .unwrap()
                    .moments()
                    .area;
                let err = (mesh.area() - exact).abs() / exact;
                let bad_jac = (0..mesh.triangles.len())
                    .filter(|&t| mesh.min_jacobian(t) <= 0.0)
                    .count();
                if angle < 25.0 || bad_jac > 0 || err > if mesh.order == 2 { 1e-4 } else { 1e-2 } {
                    failures += 1;
                    println!(
                        "case {case}: angle {angle:.2} jac {bad_jac} err {err:.2e} tris {} geometry {:?} mesh {:?}",
                        mesh.triangles.len(),
                        cfg.geometry,
                        cfg.mesh
                    );
                }
            }
            Err(e) => {
                failures += 1;
                println!("case {case}: {e} geometry {:?} mesh {:?}", cfg.geometry, cfg.mesh);
            }
        }
    }
    println!("{cases} cases, {failures} failures, worst angle {worst_angle:.2}");
}
