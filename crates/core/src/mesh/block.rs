//! The mesh of the contact tutorial's wall: a rectangular block of six-node triangles.
//!
//! The block `[x − width, x] × [center_y − height/2, center_y + height/2]` (`[wall]` keys) is cut
//! into `nx × ny` equal cells, two triangles each: `nx = ⌈width / mesh_size⌉` across and
//! `ny = ⌈height / face_size⌉` along the face, so the contact face `x = wall.x` has edges of at
//! most `face_size` (the tutorial's `r_head/20` there; its mesher grades from the face to
//! `r_head/5` inside, a structured mesh keeps the face's size throughout: a few hundred elements).
//! The face is named `contact_wall`; the left, top and bottom edges `fix` (held by the model).
//! Edges are straight, mid-edge nodes at their midpoints.

use std::collections::HashMap;

use super::{BoundaryEdge, Mesh};
use crate::config::Wall;

/// The boundary name of the wall's contact face.
pub const FACE: &str = "contact_wall";
/// The boundary name of the wall's held edges.
pub const FIXED: &str = "fix";

/// The block of the `[wall]` section.
pub fn wall_block(wall: &Wall) -> Mesh {
    let nx = ((wall.width / wall.mesh_size).ceil() as usize).max(2);
    let ny = ((wall.height / wall.face_size).ceil() as usize).max(2);
    let (x0, y0) = (wall.x - wall.width, wall.center_y - 0.5 * wall.height);
    let vid = |i: usize, j: usize| j * (nx + 1) + i;
    let mut nodes = Vec::with_capacity((2 * nx + 1) * (2 * ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            let x = if i == nx {
                wall.x // exactly on the face
            } else {
                x0 + wall.width * i as f64 / nx as f64
            };
            nodes.push([x, y0 + wall.height * j as f64 / ny as f64]);
        }
    }
    let num_vertices = nodes.len();
    let mut mids: HashMap<(usize, usize), usize> = HashMap::new();
    let mut mid = |a: usize, b: usize, nodes: &mut Vec<[f64; 2]>| -> usize {
        *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
            nodes.push([0.5 * (nodes[a][0] + nodes[b][0]), 0.5 * (nodes[a][1] + nodes[b][1])]);
            nodes.len() - 1
        })
    };
    let mut triangles = Vec::with_capacity(2 * nx * ny);
    // (cell, local edge) of each boundary edge, found while the cells are made
    let mut boundary_edges = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            // counter-clockwise: lower-left a, lower-right b, upper-right c, upper-left d
            let (a, b, c, d) = (vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1));
            for (k, [p, q, r]) in [[a, b, c], [a, c, d]].into_iter().enumerate() {
                let t = triangles.len();
                let m = [mid(p, q, &mut nodes), mid(q, r, &mut nodes), mid(r, p, &mut nodes)];
                triangles.push([p, q, r, m[0], m[1], m[2]]);
                // the lower triangle owns the bottom (edge 0) and right (edge 1) sides of the cell,
                // the upper one the top (edge 1) and left (edge 2)
                let sides: [(usize, bool, usize); 2] = if k == 0 {
                    [(0, j == 0, 1), (1, i + 1 == nx, 0)]
                } else {
                    [(1, j + 1 == ny, 1), (2, i == 0, 1)]
                };
                for (edge, on_boundary, name) in sides {
                    if on_boundary {
                        let (s, e) = [(p, q), (q, r), (r, p)][edge];
                        boundary_edges.push(BoundaryEdge {
                            nodes: [s, e, m[edge]],
                            name,
                            triangle: t,
                            local_edge: edge,
                        });
                    }
                }
            }
        }
    }
    Mesh {
        nodes,
        num_vertices,
        triangles,
        boundary_edges,
        boundary_names: vec![FACE.to_string(), FIXED.to_string()],
        region_name: "wall".into(),
        order: 2,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_block_has_its_face_on_wall_x_and_fixed_edges_around_the_rest() {
        let wall = Wall::default();
        let m = wall_block(&wall);
        let face = m.nodes_on(FACE);
        assert!(face.iter().all(|&n| m.nodes[n][0] == wall.x));
        let ny = (wall.height / wall.face_size).ceil() as usize;
        assert_eq!(face.len(), 2 * ny + 1, "every face vertex and mid-edge node");
        let fixed = m.nodes_on(FIXED);
        assert!(fixed
            .iter()
            .all(|&n| m.nodes[n][0] < wall.x - 1e-12
                || (m.nodes[n][1] - wall.center_y).abs() > 0.5 * wall.height - 1e-12));
        // area and orientation
        let area: f64 = m
            .triangles
            .iter()
            .map(|t| {
                let (a, b, c) = (m.nodes[t[0]], m.nodes[t[1]], m.nodes[t[2]]);
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
            })
            .inspect(|a| assert!(*a > 0.0, "counter-clockwise"))
            .sum();
        assert!((area - wall.width * wall.height).abs() < 1e-12);
    }
}
