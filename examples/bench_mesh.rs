//! Times the tutorial mesh and a mesh of about a million triangles.
//!
//! `cargo run --release --example bench_mesh [target_triangles]`
fn main() -> Result<(), pendulum_fem::Error> {
    let target = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1_000_000);
    let cfg = pendulum_fem::Config::default();
    let mesh = pendulum_fem::mesh::generate(&cfg)?;
    println!(
        "tutorial mesh: min angle {:.2} deg, area {:.12e} m^2",
        mesh.min_angle_deg(),
        mesh.area()
    );
    pendulum_fem::mesh::bench::bench_mesh(&cfg, Some(target))?;
    Ok(())
}
