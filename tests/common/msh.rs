//! A binary Gmsh 4.1 writer for the reader's tests (`common::msh`).
#![allow(dead_code)]

use pendulum_fem::mesh::Mesh;

/// The same mesh as `io::gmsh::write_msh` writes, in the binary variant of Gmsh 4.1 (little-endian).
pub fn binary_msh(mesh: &Mesh) -> Vec<u8> {
    let mut b: Vec<u8> = Vec::new();
    let size = |b: &mut Vec<u8>, v: usize| b.extend((v as u64).to_le_bytes());
    let int = |b: &mut Vec<u8>, v: i32| b.extend(v.to_le_bytes());
    let real = |b: &mut Vec<u8>, v: f64| b.extend(v.to_le_bytes());
    b.extend(b"$MeshFormat\n4.1 1 8\n");
    int(&mut b, 1);
    b.extend(b"\n$EndMeshFormat\n$PhysicalNames\n");
    let nb = mesh.boundary_names.len();
    b.extend(format!("{}\n", nb + 1).bytes());
    for (i, n) in mesh.boundary_names.iter().enumerate() {
        b.extend(format!("1 {} \"{n}\"\n", i + 1).bytes());
    }
    b.extend(format!("2 {} \"{}\"\n$EndPhysicalNames\n$Entities\n", nb + 1, mesh.region_name).bytes());
    for n in [0, nb, 1, 0] {
        size(&mut b, n);
    }
    for i in 0..nb {
        int(&mut b, i as i32 + 1);
        (0..6).for_each(|_| real(&mut b, 0.0));
        size(&mut b, 1);
        int(&mut b, i as i32 + 1);
        size(&mut b, 0);
    }
    int(&mut b, 1);
    (0..6).for_each(|_| real(&mut b, 0.0));
    size(&mut b, 1);
    int(&mut b, nb as i32 + 1);
    size(&mut b, nb);
    (0..nb).for_each(|i| int(&mut b, i as i32 + 1));
    b.extend(b"\n$EndEntities\n$Nodes\n");
    let nn = mesh.nodes.len();
    for v in [1, nn, 1, nn] {
        size(&mut b, v);
    }
    for v in [2, 1, 0] {
        int(&mut b, v);
    }
    size(&mut b, nn);
    (1..=nn).for_each(|t| size(&mut b, t));
    for p in &mesh.nodes {
        for v in [p[0], p[1], 0.0] {
            real(&mut b, v);
        }
    }
    b.extend(b"\n$EndNodes\n$Elements\n");
    let ne = mesh.boundary_edges.len() + mesh.triangles.len();
    let named: Vec<usize> = (0..nb)
        .filter(|&i| mesh.boundary_edges.iter().any(|e| e.name == i))
        .collect();
    for v in [named.len() + 1, ne, 1, ne] {
        size(&mut b, v);
    }
    let mut tag = 1;
    for &i in &named {
        let edges: Vec<_> = mesh.boundary_edges.iter().filter(|e| e.name == i).collect();
        for v in [1, i as i32 + 1, 8] {
            int(&mut b, v);
        }
        size(&mut b, edges.len());
        for e in edges {
            size(&mut b, tag);
            e.nodes.iter().for_each(|&n| size(&mut b, n + 1));
            tag += 1;
        }
    }
    for v in [2, 1, 9] {
        int(&mut b, v);
    }
    size(&mut b, mesh.triangles.len());
    for t in &mesh.triangles {
        size(&mut b, tag);
        t.iter().for_each(|&n| size(&mut b, n + 1));
        tag += 1;
    }
    b.extend(b"\n$EndElements\n");
    b
}
