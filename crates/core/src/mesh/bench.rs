//! Mesh-generation benchmark: times the tutorial mesh and a mesh of about a million triangles.
//!
//! The fine mesh scales every size of the configuration (maximum, rod, head, hinge edge, hinge
//! corner, circle edge) by the same factor, chosen so that the triangle count grows by the
//! requested ratio (the count of a graded mesh scales like the inverse square of its sizes).

use std::time::Instant;

use super::{generate, generate_with_stats};
use crate::config::Config;
use crate::error::Error;
use crate::mesh::Mesh;

/// One timed mesh generation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BenchResult {
    /// Triangles.
    pub triangles: usize,
    /// Vertices.
    pub vertices: usize,
    /// Nodes (vertices and mid-edge nodes).
    pub nodes: usize,
    /// Fastest wall time of the repetitions \[s\].
    pub seconds: f64,
}

/// `cfg` with every mesh size multiplied by `factor`.
pub fn scaled_config(cfg: &Config, factor: f64) -> Config {
    let mut c = cfg.clone();
    let s = cfg.mesh_sizes();
    c.mesh.max_size = s.max_size * factor;
    c.mesh.rod_size = Some(s.rod * factor);
    c.mesh.head_size = Some(s.head * factor);
    c.mesh.hinge_edge_size = Some(s.hinge_edge * factor);
    c.mesh.hinge_corner_size = Some(s.hinge_corner * factor);
    c.mesh.circle_edge_size = Some(s.circle_edge * factor);
    c
}

/// Generates the mesh of `cfg` `repeats` times (at least once) and keeps the fastest time.
pub fn time_mesh(cfg: &Config, repeats: usize) -> Result<(Mesh, BenchResult), Error> {
    let mut best = f64::INFINITY;
    let mut mesh = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        // the mesher itself, not a mesh kept in memory or on disk (`generate`)
        let m = generate_with_stats(cfg)?.0;
        best = best.min(start.elapsed().as_secs_f64());
        mesh = Some(m);
    }
    let mesh = mesh.ok_or_else(|| Error::Mesh("no repetition ran".into()))?;
    let r = BenchResult {
        triangles: mesh.triangles.len(),
        vertices: mesh.num_vertices,
        nodes: mesh.num_nodes(),
        seconds: best,
    };
    Ok((mesh, r))
}

/// Times the mesh of `cfg` (best of 10) and, if `target_triangles` is given, a refined mesh with
/// about that many triangles (one run). Prints a line per mesh and returns the results.
pub fn bench_mesh(cfg: &Config, target_triangles: Option<usize>) -> Result<Vec<BenchResult>, Error> {
    let (_, base) = time_mesh(cfg, 10)?;
    print_line("configured", &base);
    let mut out = vec![base];
    if let Some(target) = target_triangles {
        // The count of a graded mesh grows slower than 1/factor², so correct the factor twice on
        // cheaper meshes (a tenth and a third of the target) before the timed run.
        let mut factor = (base.triangles as f64 / target.max(1) as f64).sqrt();
        for fraction in [0.1f64, 0.3] {
            let probe = generate(&scaled_config(cfg, factor / fraction.sqrt()))?;
            factor *= (probe.triangles.len() as f64 / (fraction * target as f64)).sqrt();
        }
        let (_, fine) = time_mesh(&scaled_config(cfg, factor), 1)?;
        print_line(&format!("sizes x {factor:.4}"), &fine);
        out.push(fine);
    }
    Ok(out)
}

fn print_line(label: &str, r: &BenchResult) {
    println!(
        "mesh {label:>16}: {:>9} triangles {:>9} vertices {:>9} nodes {:>10.3} ms",
        r.triangles,
        r.vertices,
        r.nodes,
        r.seconds * 1e3
    );
}
