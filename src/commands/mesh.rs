//! `mesh`: generate the mesh, write it (Gmsh `.msh`, ParaView `.vtu`/`.vtm`) and report it.
//!
//! Files written into the output folder: `mesh.msh` (Gmsh 4.1 with physical names),
//! `mesh.vtu` (quadratic triangles), `mesh_<boundary>.vtu` (quadratic edges per boundary name)
//! and `mesh.vtm` (multiblock with blocks named "pendulum", "rotation", "contact_head",
//! "default"). The report is a short table, or with `json` one JSON object with exactly the keys
//! `triangles`, `vertices`, `nodes`, `min_angle_deg`, `area_m2`, `boundaries` (name → edge
//! count) and `seconds` (mesh generation time).

use std::path::Path;
use std::time::Instant;

use crate::render::{gmsh, vtm};
use crate::{mesh, Config, Error, Mesh};

/// The numbers the `mesh` command reports.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshReport {
    /// Triangles.
    pub triangles: usize,
    /// Triangle vertices.
    pub vertices: usize,
    /// All nodes (vertices and mid-edge nodes).
    pub nodes: usize,
    /// Smallest angle of the straight triangles \[deg\].
    pub min_angle_deg: f64,
    /// Area of the curved mesh \[m²\].
    pub area_m2: f64,
    /// Boundary edge counts by name.
    pub boundaries: Vec<(String, usize)>,
    /// Mesh generation time \[s\].
    pub seconds: f64,
}

impl MeshReport {
    /// The report of `mesh`, generated in `seconds`.
    pub fn new(mesh: &Mesh, seconds: f64) -> Self {
        Self {
            triangles: mesh.triangles.len(),
            vertices: mesh.num_vertices,
            nodes: mesh.num_nodes(),
            min_angle_deg: mesh.min_angle_deg(),
            area_m2: mesh.area(),
            boundaries: mesh.boundary_edge_counts(),
            seconds,
        }
    }

    /// One JSON object with the keys named in the module documentation.
    pub fn to_json(&self) -> serde_json::Value {
        let boundaries: serde_json::Map<String, serde_json::Value> = self
            .boundaries
            .iter()
            .map(|(n, c)| (n.clone(), serde_json::Value::from(*c)))
            .collect();
        serde_json::json!({
            "triangles": self.triangles,
            "vertices": self.vertices,
            "nodes": self.nodes,
            "min_angle_deg": self.min_angle_deg,
            "area_m2": self.area_m2,
            "boundaries": boundaries,
            "seconds": self.seconds,
        })
    }

    /// A short human-readable table.
    pub fn table(&self) -> String {
        let mut s = String::new();
        s.push_str(&format!("{:<22}{:>14}\n", "triangles", self.triangles));
        s.push_str(&format!("{:<22}{:>14}\n", "vertices", self.vertices));
        s.push_str(&format!("{:<22}{:>14}\n", "nodes", self.nodes));
        s.push_str(&format!("{:<22}{:>14.2}\n", "minimum angle [deg]", self.min_angle_deg));
        s.push_str(&format!("{:<22}{:>16.10e}\n", "area [m^2]", self.area_m2));
        for (name, count) in &self.boundaries {
            s.push_str(&format!("{:<22}{:>14}\n", format!("edges \"{name}\""), count));
        }
        s.push_str(&format!("{:<22}{:>14.3}\n", "time [ms]", self.seconds * 1e3));
        s
    }
}

/// Generates the mesh of `cfg`, writes its files into `out_dir` (created if needed) and prints
/// a table (or one JSON object with `json`).
pub fn mesh_command(cfg: &Config, out_dir: &Path, json: bool) -> Result<(), Error> {
    let start = Instant::now();
    let mesh = mesh::generate(cfg)?;
    if let Some(warning) = mesh::max_size_warning(cfg, &mesh) {
        eprintln!("{warning}");
    }
    let seconds = start.elapsed().as_secs_f64();
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    gmsh::write_msh(&out_dir.join("mesh.msh"), &mesh)?;
    vtm::write_mesh_blocks(out_dir, &mesh)?;
    let report = MeshReport::new(&mesh, seconds);
    if json {
        println!("{}", report.to_json());
    } else {
        print!("{}", report.table());
        println!(
            "written to {}: mesh.msh, mesh.vtm (mesh.vtu, mesh_<boundary>.vtu)",
            out_dir.display()
        );
    }
    Ok(())
}
