//! The `[geometry]` and `[mesh]` sections: the pendulum's shape, and the mesh sizes whose
//! defaults are fractions of it ([`MeshSizes`], [`Config::mesh_sizes`]), with their rules.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

use super::ranges::{non_negative, positive, range, within, Mistakes};
use super::Config;

/// Pendulum geometry (the tutorial's `r_rod`, `r_head`, `r_hole`, `l_center`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Geometry {
    /// Half-width of the rod \[m\].
    pub rod_half_width: f64,
    /// Outer radius of the head \[m\].
    pub head_radius: f64,
    /// Radius of the hole in the head \[m\]; 0 means no hole.
    pub hole_radius: f64,
    /// Distance from the pivot to the head centre \[m\].
    pub head_center_distance: f64,
    /// Out-of-plane thickness \[m\].
    pub thickness: f64,
}

impl Default for Geometry {
    fn default() -> Self {
        Self {
            rod_half_width: 0.015,
            head_radius: 0.06,
            hole_radius: 0.03,
            head_center_distance: 0.24,
            thickness: 0.01,
        }
    }
}

impl Geometry {
    /// The `[geometry]` rules: positive sizes, the hole inside the head, the rod narrower than
    /// the head and with a free length (the relations once the sizes are valid).
    pub(super) fn validate(&self, m: &mut Mistakes) {
        let g = self;
        let sizes = [
            m.check(positive("geometry.rod_half_width", g.rod_half_width, "m")),
            m.check(positive("geometry.head_radius", g.head_radius, "m")),
            m.check(non_negative("geometry.hole_radius", g.hole_radius, "m")),
            m.check(positive("geometry.head_center_distance", g.head_center_distance, "m")),
        ];
        m.check(positive("geometry.thickness", g.thickness, "m"));
        if sizes.contains(&false) {
            return;
        }
        if g.hole_radius >= g.head_radius {
            m.keep(range(
                "geometry.hole_radius",
                g.hole_radius,
                &format!(
                    "0 <= hole_radius < head_radius = {} m (the hole must lie inside the head)",
                    g.head_radius
                ),
            ));
        }
        if g.rod_half_width >= g.head_radius {
            m.keep(range(
                "geometry.rod_half_width",
                g.rod_half_width,
                &format!(
                    "0 < rod_half_width < head_radius = {} m (the rod must be narrower than the head)",
                    g.head_radius
                ),
            ));
            return;
        }
        // The rod [−r, r] × [0, l] must reach into the head disc and must not end inside the hole:
        // its end meets the head circle at distance l − sqrt(R² − r²) from the pivot, which must be > 0,
        // and the rod end (the head centre) lies in the hole, so the rod's sides must meet the head ring
        // outside the hole: sqrt(R² − r²) > sqrt(max(h² − r², 0)) holds whenever R > h.
        let reach = (g.head_radius * g.head_radius - g.rod_half_width * g.rod_half_width).sqrt();
        if g.head_center_distance <= reach {
            m.keep(range(
                "geometry.head_center_distance",
                g.head_center_distance,
                &format!(
                    "head_center_distance > sqrt(head_radius² − rod_half_width²) = {reach:.6} m \
                     (the head would swallow the pivot; the rod must have a free length)"
                ),
            ));
        }
    }
}

/// Mesh sizes. The local sizes default to the tutorial's fractions of the geometry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MeshConfig {
    /// Global maximum element size \[m\].
    pub max_size: f64,
    /// Geometric order: 1 (straight-sided) or 2 (curved six-node triangles on the circles).
    pub order: u32,
    /// Size in the rod \[m\]; default `rod_half_width / 2`.
    pub rod_size: Option<f64>,
    /// Size in the head \[m\]; default `head_radius / 5`.
    pub head_size: Option<f64>,
    /// Size along the hinge edge \[m\]; default `rod_half_width / 10`.
    pub hinge_edge_size: Option<f64>,
    /// Size at the two hinge corners \[m\]; default `rod_half_width / 20`.
    pub hinge_corner_size: Option<f64>,
    /// Size along the head and hole circles \[m\]; default `head_radius / 20`.
    pub circle_edge_size: Option<f64>,
    /// Growth rate of the size away from small features (Netgen's `grading`), 0.05 to 1.
    pub grading: f64,
    /// Divides every size above (the global maximum and each local size, given or derived):
    /// 2 halves them all (the default pendulum: 1233 → 3436 triangles). 0.1 to 100.
    pub refine: f64,
    /// A Gmsh 4.1 mesh to swing instead of the generated pendulum (ASCII or binary, 3- or 6-node
    /// triangles, the hinge edge in a physical curve group named `rotation`); the geometry and
    /// the sizes above are then unused, except `geometry.thickness`.
    pub file: Option<PathBuf>,
}

impl Default for MeshConfig {
    fn default() -> Self {
        Self {
            max_size: 0.03,
            order: 2,
            rod_size: None,
            head_size: None,
            hinge_edge_size: None,
            hinge_corner_size: None,
            circle_edge_size: None,
            grading: 0.3,
            refine: 1.0,
            file: None,
        }
    }
}

/// Local mesh sizes with the geometry-derived defaults filled in \[m\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshSizes {
    /// Global maximum.
    pub max_size: f64,
    /// In the rod.
    pub rod: f64,
    /// In the head.
    pub head: f64,
    /// Along the hinge edge.
    pub hinge_edge: f64,
    /// At the hinge corners.
    pub hinge_corner: f64,
    /// Along the circles.
    pub circle_edge: f64,
    /// Growth rate away from small features.
    pub grading: f64,
}

impl Config {
    /// The local mesh sizes, with defaults derived from the geometry as in the tutorial, each
    /// divided by `mesh.refine`.
    pub fn mesh_sizes(&self) -> MeshSizes {
        self.mesh.sizes(&self.geometry)
    }
}

impl MeshConfig {
    /// The local mesh sizes for geometry `g` ([`Config::mesh_sizes`]).
    fn sizes(&self, g: &Geometry) -> MeshSizes {
        let m = self;
        let r = m.refine;
        MeshSizes {
            max_size: m.max_size / r,
            rod: m.rod_size.unwrap_or(g.rod_half_width / 2.0) / r,
            head: m.head_size.unwrap_or(g.head_radius / 5.0) / r,
            hinge_edge: m.hinge_edge_size.unwrap_or(g.rod_half_width / 10.0) / r,
            hinge_corner: m.hinge_corner_size.unwrap_or(g.rod_half_width / 20.0) / r,
            circle_edge: m.circle_edge_size.unwrap_or(g.head_radius / 20.0) / r,
            grading: m.grading,
        }
    }

    /// The `[mesh]` rules (the smallest size relative to the geometry `g`, when it is valid).
    pub(super) fn validate(&self, g: Option<&Geometry>, m: &mut Mistakes) {
        let c = self;
        let mut valid = m.check(positive("mesh.max_size", c.max_size, "m"));
        if !(c.order == 1 || c.order == 2) {
            m.push(
                "mesh.order",
                format!("mesh.order = {}: allowed values are 1 and 2", c.order),
            );
        }
        for (key, v) in [
            ("mesh.rod_size", c.rod_size),
            ("mesh.head_size", c.head_size),
            ("mesh.hinge_edge_size", c.hinge_edge_size),
            ("mesh.hinge_corner_size", c.hinge_corner_size),
            ("mesh.circle_edge_size", c.circle_edge_size),
        ] {
            if let Some(v) = v {
                valid &= m.check(positive(key, v, "m"));
            }
        }
        valid &= m.check(within("mesh.grading", c.grading, 0.05, 1.0, ""));
        valid &= m.check(within("mesh.refine", c.refine, 0.1, 100.0, "(divides every mesh size)"));
        let Some(g) = g.filter(|_| valid) else { return };
        let sizes = self.sizes(g);
        let smallest = [
            sizes.max_size,
            sizes.rod,
            sizes.head,
            sizes.hinge_edge,
            sizes.hinge_corner,
            sizes.circle_edge,
        ]
        .into_iter()
        .fold(f64::INFINITY, f64::min);
        let scale = g.head_center_distance + g.head_radius;
        if smallest < scale * 1e-5 {
            m.push(
                "mesh",
                format!(
                    "mesh sizes: the smallest local size {smallest:e} m is below 1e-5 × the pendulum length ({:e} m); \
                     allowed: sizes >= {:e} m",
                    scale,
                    scale * 1e-5
                ),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refine_divides_every_mesh_size() {
        let base = Config::default().mesh_sizes();
        let cfg = Config::load(None, &["mesh.refine=2".into(), "mesh.rod_size=0.006".into()]).unwrap();
        let s = cfg.mesh_sizes();
        for (a, b) in [
            (s.max_size, base.max_size),
            (s.head, base.head),
            (s.hinge_edge, base.hinge_edge),
            (s.hinge_corner, base.hinge_corner),
            (s.circle_edge, base.circle_edge),
            (s.rod, 0.006),
        ] {
            assert_eq!(a, b / 2.0);
        }
        let err = Config::load(None, &["mesh.refine=0".into()]).unwrap_err().to_string();
        assert!(err.contains("mesh.refine") && err.contains("0.1 to 100"), "{err}");
    }
}
