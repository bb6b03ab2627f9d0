//! Mesh files: Gmsh 4.1 and the VTU multiblock parse back with the counts written; the mesh
//! command writes them and reports the agreed JSON keys.

use crate::common;

use std::path::PathBuf;

use common::tutorial;
use pendulum_fem::commands::mesh::{mesh_command, MeshReport};
use pendulum_fem::mesh::generate;
use pendulum_fem::render::{gmsh, vtm};

fn out_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temporary folder");
    dir
}

/// The lines of section `$name … $Endname`.
fn section<'a>(text: &'a str, name: &str) -> Vec<&'a str> {
    let start = format!("${name}");
    let end = format!("$End{name}");
    text.lines()
        .skip_while(|l| *l != start)
        .skip(1)
        .take_while(|l| *l != end)
        .collect()
}

fn numbers(line: &str) -> Vec<f64> {
    line.split_whitespace().map(|w| w.parse().expect("a number")).collect()
}

#[test]
fn gmsh_file_parses_back_with_the_written_counts_and_names() {
    let mesh = generate(&tutorial()).expect("mesh");
    let dir = out_dir("gmsh");
    let path = dir.join("mesh.msh");
    gmsh::write_msh(&path, &mesh).expect("written");
    let text = std::fs::read_to_string(&path).expect("readable");
    assert_eq!(section(&text, "MeshFormat"), vec!["4.1 0 8"]);

    let names = section(&text, "PhysicalNames");
    assert_eq!(names[0], "4");
    for expected in [
        "1 1 \"rotation\"",
        "1 2 \"contact_head\"",
        "1 3 \"default\"",
        "2 4 \"pendulum\"",
    ] {
        assert!(names.contains(&expected), "missing physical name {expected}");
    }

    let nodes = section(&text, "Nodes");
    let header = numbers(nodes[0]);
    assert_eq!(header, vec![1.0, mesh.num_nodes() as f64, 1.0, mesh.num_nodes() as f64]);
    assert_eq!(
        nodes.len(),
        2 + 2 * mesh.num_nodes(),
        "tags and coordinates of every node"
    );
    let first = numbers(nodes[2 + mesh.num_nodes()]);
    assert_eq!([first[0], first[1]], mesh.nodes[0], "coordinates round-trip exactly");

    let elements = section(&text, "Elements");
    let header = numbers(elements[0]);
    let total = mesh.triangles.len() + mesh.boundary_edges.len();
    assert_eq!(header[1] as usize, total);
    let mut i = 1;
    let mut lines = 0;
    let mut triangles = 0;
    while i < elements.len() {
        let block = numbers(elements[i]);
        let (kind, count) = (block[2] as u32, block[3] as usize);
        for l in &elements[i + 1..i + 1 + count] {
            let width = numbers(l).len();
            match kind {
                gmsh::GMSH_LINE3 => assert_eq!(width, 4),
                gmsh::GMSH_TRIANGLE6 => assert_eq!(width, 7),
                other => panic!("unexpected element type {other}"),
            }
        }
        if kind == gmsh::GMSH_LINE3 {
            lines += count;
        } else {
            triangles += count;
        }
        i += 1 + count;
    }
    assert_eq!((lines, triangles), (mesh.boundary_edges.len(), mesh.triangles.len()));
}

fn attribute(text: &str, name: &str) -> usize {
    let key = format!("{name}=\"");
    let start = text.find(&key).expect("attribute") + key.len();
    text[start..]
        .split('"')
        .next()
        .expect("value")
        .parse()
        .expect("a count")
}

#[test]
fn vtu_multiblock_has_named_blocks_with_the_written_counts() {
    let mesh = generate(&tutorial()).expect("mesh");
    let dir = out_dir("vtm");
    let written = vtm::write_mesh_blocks(&dir, &mesh).expect("written");
    assert_eq!(written.len(), 5, "mesh.vtu, three boundary files, mesh.vtm");
    // The XML header is text; the compressed arrays after it are not.
    let read = |name: &str| String::from_utf8_lossy(&std::fs::read(dir.join(name)).expect(name)).into_owned();
    let main = read("mesh.vtu");
    assert_eq!(attribute(&main, "NumberOfPoints"), mesh.num_nodes());
    assert_eq!(attribute(&main, "NumberOfCells"), mesh.triangles.len());
    assert!(main.contains("Name=\"region\""));
    for name in ["rotation", "contact_head", "default"] {
        let text = read(&format!("mesh_{name}.vtu"));
        let edges = mesh.edges_named(name).count();
        assert_eq!(attribute(&text, "NumberOfCells"), edges, "{name}");
        assert_eq!(attribute(&text, "NumberOfPoints"), mesh.nodes_on(name).len(), "{name}");
    }
    let index = std::fs::read_to_string(dir.join("mesh.vtm")).expect("mesh.vtm");
    for name in ["pendulum", "rotation", "contact_head", "default"] {
        assert!(index.contains(&format!("name=\"{name}\"")), "block {name} missing");
    }
}

#[test]
fn mesh_command_writes_all_files_and_reports_the_agreed_json_keys() {
    let dir = out_dir("command").join("new-subfolder");
    mesh_command(&tutorial(), &dir, true).expect("mesh command");
    for file in [
        "mesh.msh",
        "mesh.vtu",
        "mesh.vtm",
        "mesh_rotation.vtu",
        "mesh_contact_head.vtu",
        "mesh_default.vtu",
    ] {
        assert!(dir.join(file).is_file(), "{file} not written");
    }
    let mesh = generate(&tutorial()).expect("mesh");
    let json = MeshReport::new(&mesh, 0.01).to_json();
    let object = json.as_object().expect("one JSON object");
    let mut keys: Vec<&str> = object.keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "area_m2",
            "boundaries",
            "min_angle_deg",
            "nodes",
            "seconds",
            "triangles",
            "vertices"
        ]
    );
    assert_eq!(object["triangles"], mesh.triangles.len());
    assert_eq!(object["boundaries"]["rotation"], mesh.edges_named("rotation").count());
}
