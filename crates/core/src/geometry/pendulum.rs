//! The pendulum as the tutorial builds it: its parameter checks, and the rod ∪ head − hole
//! shape with the boundary names ("rotation", "contact_head", "default") and the local mesh
//! sizes of its edges, regions and hinge corners.

use super::{Corner, Shape, CONTACT_HEAD, DEFAULT, ROTATION};
use crate::config::{Geometry, MeshSizes};
use crate::error::Error;
use std::f64::consts::PI;

/// Checks the pendulum parameters; each error names its parameter.
pub fn check_parameters(g: &Geometry, sizes: &MeshSizes) -> Result<(), Error> {
    let positive = |name: &str, v: f64| {
        if v > 0.0 && v.is_finite() {
            Ok(())
        } else {
            Err(Error::Geometry(format!("{name} = {v}: must be a finite value > 0 m")))
        }
    };
    positive("geometry.rod_half_width", g.rod_half_width)?;
    positive("geometry.head_radius", g.head_radius)?;
    positive("geometry.head_center_distance", g.head_center_distance)?;
    if !(g.hole_radius >= 0.0 && g.hole_radius.is_finite()) {
        return Err(Error::Geometry(format!(
            "geometry.hole_radius = {}: must be a finite value >= 0 m (0 = no hole)",
            g.hole_radius
        )));
    }
    if g.hole_radius >= g.head_radius {
        return Err(Error::Geometry(format!(
            "geometry.hole_radius = {}: the hole must lie inside the head (hole_radius < head_radius = {} m)",
            g.hole_radius, g.head_radius
        )));
    }
    if g.rod_half_width >= g.head_radius {
        return Err(Error::Geometry(format!(
            "geometry.rod_half_width = {}: the rod must be narrower than the head (rod_half_width < head_radius = {} m)",
            g.rod_half_width, g.head_radius
        )));
    }
    let reach = (g.head_radius * g.head_radius - g.rod_half_width * g.rod_half_width).sqrt();
    if g.head_center_distance <= reach {
        return Err(Error::Geometry(format!(
            "geometry.head_center_distance = {}: the rod is too short to reach the head with a free length \
             (need head_center_distance > sqrt(head_radius² − rod_half_width²) = {reach:.6} m)",
            g.head_center_distance
        )));
    }
    for (name, v) in [
        ("mesh.max_size", sizes.max_size),
        ("mesh.rod_size", sizes.rod),
        ("mesh.head_size", sizes.head),
        ("mesh.hinge_edge_size", sizes.hinge_edge),
        ("mesh.hinge_corner_size", sizes.hinge_corner),
        ("mesh.circle_edge_size", sizes.circle_edge),
    ] {
        positive(name, v)?;
    }
    if !(sizes.grading > 0.0 && sizes.grading.is_finite()) {
        return Err(Error::Geometry(format!(
            "mesh.grading = {}: must be a finite value > 0",
            sizes.grading
        )));
    }
    Ok(())
}

/// The pendulum as the tutorial builds it: rod `[−r, r] × [0, l]` ∪ head disc (centre `(0, l)`,
/// radius `R`) − hole (radius `r_hole`, none if 0), rotated 180° about the origin, so it hangs
/// in −y with the pivot at the origin and the hinge edge on `y = 0`.
///
/// Names: "rotation" (hinge edge, size `hinge_edge`), "contact_head" (outer head circle, size
/// `circle_edge`), "default" (rod sides and hole, the hole circle with size `circle_edge`).
/// Region sizes: rod `rod`, head disc `head`; corner sizes `hinge_corner` at `(±r, 0)`.
pub fn pendulum(g: &Geometry, sizes: &MeshSizes) -> Result<Shape, Error> {
    check_parameters(g, sizes)?;
    let (r, l, big_r) = (g.rod_half_width, g.head_center_distance, g.head_radius);
    let mut bar = Shape::rectangle(-r, 0.0, r, l).with_region_size("rod", sizes.rod);
    bar.edges[0].name = ROTATION.into();
    bar.edges[0].size = Some(sizes.hinge_edge);
    bar.corners.push(Corner {
        point: [-r, 0.0],
        size: sizes.hinge_corner,
    });
    bar.corners.push(Corner {
        point: [r, 0.0],
        size: sizes.hinge_corner,
    });
    let circ = Shape::circle([0.0, l], big_r)
        .with_edges(CONTACT_HEAD, Some(sizes.circle_edge))
        .with_region_size("head", sizes.head);
    let mut shape = circ.union(bar);
    if g.hole_radius > 0.0 {
        let hole = Shape::circle([0.0, l], g.hole_radius).with_edges(DEFAULT, Some(sizes.circle_edge));
        shape = shape.difference(hole);
    }
    Ok(shape.rotated([0.0, 0.0], PI))
}
