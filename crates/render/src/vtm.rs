//! The mesh as a ParaView multiblock (`.vtm`): the region and each named boundary as its own
//! block, so names are usable in ParaView.
//!
//! `mesh.vtm` lists the blocks by name: the region (`mesh.vtu`, quadratic triangles with the cell
//! field `region`) and one file per boundary name (`mesh_<name>.vtu`, quadratic edges with the
//! cell field `boundary`, only the nodes they use).

use std::io::Write;
use std::path::{Path, PathBuf};

use super::vtu::{write_mesh_vtu, write_vtu, Cells, Grid, VTK_QUADRATIC_EDGE};
use super::{Field, FieldData};
use crate::{Error, Mesh};
use pendulum_fem_core::store::write_atomically;

/// Writes `blocks` (name, file relative to the `.vtm`) as a multiblock data set.
pub fn write_vtm(path: &Path, blocks: &[(String, String)]) -> Result<(), Error> {
    write_atomically(path, |w: &mut dyn Write| {
        writeln!(w, r#"<?xml version="1.0"?>"#)?;
        writeln!(
            w,
            r#"<VTKFile type="vtkMultiBlockDataSet" version="1.0" byte_order="LittleEndian" header_type="UInt64">"#
        )?;
        writeln!(w, "<vtkMultiBlockDataSet>")?;
        for (i, (name, file)) in blocks.iter().enumerate() {
            writeln!(w, r#"<DataSet index="{i}" name="{name}" file="{file}"/>"#)?;
        }
        writeln!(w, "</vtkMultiBlockDataSet>\n</VTKFile>")
    })
}

/// Writes `mesh.vtu`, one `mesh_<name>.vtu` per boundary name and `mesh.vtm` tying them together
/// into `dir`; returns the paths written (the `.vtm` last).
pub fn write_mesh_blocks(dir: &Path, mesh: &Mesh) -> Result<Vec<PathBuf>, Error> {
    let mut written = Vec::new();
    let region = vec![0.0; mesh.triangles.len()];
    let main = dir.join("mesh.vtu");
    write_mesh_vtu(
        &main,
        mesh,
        &[],
        &[Field {
            name: "region",
            data: FieldData::Scalar(&region),
        }],
    )?;
    written.push(main);
    let mut blocks = vec![(mesh.region_name.clone(), "mesh.vtu".to_string())];
    for (i, name) in mesh.boundary_names.iter().enumerate() {
        let edges: Vec<_> = mesh.boundary_edges.iter().filter(|e| e.name == i).collect();
        let mut local = vec![usize::MAX; mesh.nodes.len()];
        let mut points = Vec::new();
        let mut connectivity = Vec::with_capacity(3 * edges.len());
        for e in &edges {
            for &n in &e.nodes {
                if local[n] == usize::MAX {
                    local[n] = points.len();
                    points.push(mesh.nodes[n]);
                }
                connectivity.push(local[n]);
            }
        }
        let ids = vec![i as f64; edges.len()];
        let file = format!("mesh_{name}.vtu");
        let path = dir.join(&file);
        let cells = [Cells {
            connectivity: &connectivity,
            nodes_per_cell: 3,
            vtk_type: VTK_QUADRATIC_EDGE,
        }];
        write_vtu(
            &path,
            &Grid {
                points: &points,
                cells: &cells,
                point_data: &[],
                cell_data: &[Field {
                    name: "boundary",
                    data: FieldData::Scalar(&ids),
                }],
                field_data: &[],
            },
        )?;
        written.push(path);
        blocks.push((name.clone(), file));
    }
    let vtm = dir.join("mesh.vtm");
    write_vtm(&vtm, &blocks)?;
    written.push(vtm);
    Ok(written)
}
