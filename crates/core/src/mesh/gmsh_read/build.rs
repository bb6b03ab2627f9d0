//! The conversion of a parsed file to our [`Mesh`]: corner then mid-edge nodes by tag,
//! counter-clockwise 6-node triangles, boundary edges named by the physical groups of the line
//! elements (the hinge first), and the region's name.

use std::collections::HashMap;

use super::{RawMesh, HINGE_NAME};
use crate::error::Error;
use crate::mesh::{BoundaryEdge, Mesh};

pub(super) fn build_mesh(raw: RawMesh, source: &str) -> Result<Mesh, Error> {
    let err = |m: String| Error::Input(format!("{source}: {m}"));
    if raw.triangles.is_empty() {
        return Err(err("no triangles (element types 2 or 9) in $Elements".into()));
    }
    let six = raw.triangles[0].2.len() == 6;
    if let Some(t) = raw.triangles.iter().find(|t| (t.2.len() == 6) != six) {
        return Err(err(format!(
            "element {}: 3- and 6-node triangles are mixed; use one kind",
            t.0
        )));
    }
    let extent = raw
        .nodes
        .values()
        .fold(0.0f64, |a, p| a.max(p[0].abs()).max(p[1].abs()));
    let point = |tag: u64, element: u64| -> Result<[f64; 2], Error> {
        let p = raw
            .nodes
            .get(&tag)
            .ok_or_else(|| err(format!("element {element} uses node {tag}, which is not in $Nodes")))?;
        if p[2].abs() > 1e-9 * extent.max(1e-300) {
            return Err(err(format!(
                "node {tag} has z = {}: the mesh must lie in the plane z = 0",
                p[2]
            )));
        }
        Ok([p[0], p[1]])
    };
    // corners and mid nodes by tag
    let mut corner_tags: Vec<u64> = Vec::new();
    let mut mid_tags: Vec<u64> = Vec::new();
    for (tag, _, nodes) in &raw.triangles {
        for &n in &nodes[..3] {
            point(n, *tag)?;
            corner_tags.push(n);
        }
        for &n in &nodes[3..] {
            point(n, *tag)?;
            mid_tags.push(n);
        }
    }
    corner_tags.sort_unstable();
    corner_tags.dedup();
    mid_tags.sort_unstable();
    mid_tags.dedup();
    if let Some(n) = mid_tags.iter().find(|n| corner_tags.binary_search(n).is_ok()) {
        return Err(err(format!(
            "node {n} is a corner of one triangle and a mid-edge node of another"
        )));
    }
    let mut index: HashMap<u64, usize> = HashMap::with_capacity(corner_tags.len() + mid_tags.len());
    let mut nodes: Vec<[f64; 2]> = Vec::with_capacity(corner_tags.len() + mid_tags.len());
    for &t in corner_tags.iter().chain(&mid_tags) {
        index.insert(t, nodes.len());
        nodes.push([raw.nodes[&t][0], raw.nodes[&t][1]]);
    }
    let num_vertices = corner_tags.len();
    // triangles, counter-clockwise, with one mid node per edge
    let mut mid_of: HashMap<(usize, usize), usize> = HashMap::new();
    let mut uses: HashMap<(usize, usize), usize> = HashMap::new();
    let mut triangles = Vec::with_capacity(raw.triangles.len());
    for (tag, _, tn) in &raw.triangles {
        let v: Vec<usize> = tn.iter().map(|t| index[t]).collect();
        let [a, b, c] = [nodes[v[0]], nodes[v[1]], nodes[v[2]]];
        let area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if area2 == 0.0 || area2.is_nan() || v[0] == v[1] || v[1] == v[2] || v[0] == v[2] {
            return Err(err(format!(
                "triangle element {tag} is degenerate (zero area or a repeated node)"
            )));
        }
        let mut t = if six {
            [v[0], v[1], v[2], v[3], v[4], v[5]]
        } else {
            [v[0], v[1], v[2], usize::MAX, usize::MAX, usize::MAX]
        };
        if area2 < 0.0 {
            t = [t[0], t[2], t[1], t[5], t[4], t[3]];
        }
        for k in 0..3 {
            let (p, q) = (t[k], t[(k + 1) % 3]);
            let key = (p.min(q), p.max(q));
            let count = uses.entry(key).or_insert(0);
            *count += 1;
            if *count > 2 {
                return Err(err(format!(
                    "triangle element {tag}: its edge between nodes {} and {} belongs to three triangles",
                    corner_tags[p], corner_tags[q]
                )));
            }
            if six {
                let m = *mid_of.entry(key).or_insert(t[3 + k]);
                if m != t[3 + k] {
                    return Err(err(format!(
                        "triangle element {tag}: the edge between nodes {} and {} has two different mid nodes",
                        corner_tags[p], corner_tags[q]
                    )));
                }
            } else {
                let m = *mid_of.entry(key).or_insert_with(|| {
                    nodes.push([(nodes[p][0] + nodes[q][0]) / 2.0, (nodes[p][1] + nodes[q][1]) / 2.0]);
                    nodes.len() - 1
                });
                t[3 + k] = m;
            }
        }
        triangles.push(t);
    }
    // boundary names from the physical groups of the line elements
    let physical_name = |dim: i32, entity: i32| -> Option<&String> {
        raw.entity_physicals
            .get(&(dim, entity))?
            .iter()
            .find_map(|p| raw.physical_names.get(&(dim, *p)))
    };
    let mut line_name: HashMap<(usize, usize), (String, u64)> = HashMap::new();
    for (tag, entity, ln) in &raw.lines {
        let Some(name) = physical_name(1, *entity) else {
            continue;
        };
        let ends: Vec<usize> = ln[..2]
            .iter()
            .map(|t| {
                index.get(t).copied().filter(|&i| i < num_vertices).ok_or_else(|| {
                    err(format!(
                        "line element {tag} (physical \"{name}\") ends at node {t}, which is no triangle corner"
                    ))
                })
            })
            .collect::<Result<_, _>>()?;
        let key = (ends[0].min(ends[1]), ends[0].max(ends[1]));
        if uses.get(&key) != Some(&1) {
            return Err(err(format!(
                "line element {tag} (physical \"{name}\") is not on the boundary of the triangles"
            )));
        }
        line_name.insert(key, (name.clone(), *tag));
    }
    let mut names: Vec<String> = Vec::new();
    let mut groups: Vec<(i32, &String)> = raw
        .physical_names
        .iter()
        .filter(|((dim, _), _)| *dim == 1)
        .map(|((_, tag), name)| (*tag, name))
        .collect();
    groups.sort();
    for (_, name) in groups {
        if line_name.values().any(|(n, _)| n == name) && !names.contains(name) {
            names.push(name.clone());
        }
    }
    if !names.iter().any(|n| n == HINGE_NAME) {
        return Err(err(format!(
            "no boundary edges in a physical curve group named \"{HINGE_NAME}\": name the hinge edge's physical \
             group {HINGE_NAME} (Physical Curve(\"{HINGE_NAME}\") = {{…}} in a .geo file)"
        )));
    }
    // the hinge first, as in generated meshes
    let hinge = names.iter().position(|n| n == HINGE_NAME).expect("present");
    let h = names.remove(hinge);
    names.insert(0, h);
    let mut boundary_edges = Vec::new();
    let mut unnamed = false;
    for (ti, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (p, q) = (t[k], t[(k + 1) % 3]);
            let key = (p.min(q), p.max(q));
            if uses[&key] != 1 {
                continue;
            }
            let name = match line_name.get(&key) {
                Some((n, _)) => names.iter().position(|x| x == n).expect("collected"),
                None => {
                    unnamed = true;
                    usize::MAX
                }
            };
            boundary_edges.push(BoundaryEdge {
                nodes: [p, q, t[3 + k]],
                name,
                triangle: ti,
                local_edge: k,
            });
        }
    }
    if unnamed {
        let default = match names.iter().position(|n| n == "default") {
            Some(i) => i,
            None => {
                names.push("default".into());
                names.len() - 1
            }
        };
        for e in &mut boundary_edges {
            if e.name == usize::MAX {
                e.name = default;
            }
        }
    }
    let region_name = raw
        .triangles
        .first()
        .and_then(|(_, entity, _)| physical_name(2, *entity))
        .cloned()
        .unwrap_or_else(|| "pendulum".into());
    Ok(Mesh {
        nodes,
        num_vertices,
        triangles,
        boundary_edges,
        boundary_names: names,
        region_name,
        order: if six { 2 } else { 1 },
    })
}
