//! Test fixtures: small structured meshes with the names the solver expects.
#![allow(dead_code)]

use pendulum_fem::mesh::{BoundaryEdge, Mesh};

/// A rectangle `[−w, w] × [−l, 0]` hanging from its top edge (named "rotation"; the other sides
/// "default"), `nx × ny` cells each split into two six-node triangles, straight mid-edge nodes.
pub fn hanging_rectangle(w: f64, l: f64, nx: usize, ny: usize) -> Mesh {
    // vertex grid
    let vid = |i: usize, j: usize| j * (nx + 1) + i;
    let mut nodes = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            nodes.push([-w + 2.0 * w * i as f64 / nx as f64, -l * j as f64 / ny as f64]);
        }
    }
    let num_vertices = nodes.len();
    let mut mids = std::collections::HashMap::new();
    let mut mid = |a: usize, b: usize, nodes: &mut Vec<[f64; 2]>| -> usize {
        let key = (a.min(b), a.max(b));
        *mids.entry(key).or_insert_with(|| {
            let p = [(nodes[a][0] + nodes[b][0]) / 2.0, (nodes[a][1] + nodes[b][1]) / 2.0];
            nodes.push(p);
            nodes.len() - 1
        })
    };
    let mut triangles = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            // y decreases with j: (i, j+1) is below (i, j). Counter-clockwise in (x, y):
            let (a, b, c, d) = (vid(i, j + 1), vid(i + 1, j + 1), vid(i + 1, j), vid(i, j));
            for [p, q, r] in [[a, b, c], [a, c, d]] {
                let m0 = mid(p, q, &mut nodes);
                let m1 = mid(q, r, &mut nodes);
                let m2 = mid(r, p, &mut nodes);
                triangles.push([p, q, r, m0, m1, m2]);
            }
        }
    }
    // boundary edges, domain on the left
    let mut boundary_edges = Vec::new();
    let find = |triangles: &Vec<[usize; 6]>, a: usize, b: usize| -> (usize, usize) {
        for (t, tri) in triangles.iter().enumerate() {
            for (k, [s, e, _]) in [[0, 1, 3], [1, 2, 4], [2, 0, 5]].iter().enumerate() {
                if tri[*s] == a && tri[*e] == b {
                    return (t, k);
                }
            }
        }
        panic!("edge {a}-{b} not found");
    };
    let mut push = |a: usize, b: usize, name: usize, triangles: &Vec<[usize; 6]>| {
        let (t, k) = find(triangles, a, b);
        let m = triangles[t][[3, 4, 5][k]];
        boundary_edges.push(BoundaryEdge {
            nodes: [a, b, m],
            name,
            triangle: t,
            local_edge: k,
        });
    };
    for i in 0..nx {
        push(vid(i + 1, 0), vid(i, 0), 1, &triangles); // top, right to left
        push(vid(i, ny), vid(i + 1, ny), 0, &triangles); // bottom
    }
    for j in 0..ny {
        push(vid(nx, j + 1), vid(nx, j), 0, &triangles); // right side, upwards
        push(vid(0, j), vid(0, j + 1), 0, &triangles); // left side, downwards
    }
    Mesh {
        nodes,
        num_vertices,
        triangles,
        boundary_edges,
        boundary_names: vec!["default".into(), "rotation".into(), "contact_head".into()],
        region_name: "pendulum".into(),
        order: 2,
    }
}
