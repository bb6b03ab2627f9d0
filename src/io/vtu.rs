//! VTK XML unstructured grids (`.vtu`) for ParaView and meshio.
//!
//! ASCII format, points in 3-D with `z = 0`. Six-node triangles are written as
//! `VTK_QUADRATIC_TRIANGLE` (type 22), whose node order (three corners, then the mid-edge nodes of
//! the edges 0→1, 1→2, 2→0) is exactly ours; three-node edges as `VTK_QUADRATIC_EDGE` (type 21,
//! corners first, then the mid node). Files are written to a temporary name and renamed into place,
//! so a crash never leaves a half-written file under the final name.

use std::io::Write;
use std::path::Path;

use super::{Field, FieldData};
use crate::{Error, Mesh};

/// VTK cell type of the quadratic triangle.
pub const VTK_QUADRATIC_TRIANGLE: u8 = 22;
/// VTK cell type of the quadratic edge.
pub const VTK_QUADRATIC_EDGE: u8 = 21;

/// Cells of one type, flat connectivity.
#[derive(Clone, Copy, Debug)]
pub struct Cells<'a> {
    /// Node indices, `nodes_per_cell` per cell.
    pub connectivity: &'a [usize],
    /// Nodes in each cell.
    pub nodes_per_cell: usize,
    /// VTK cell type.
    pub vtk_type: u8,
}

/// Writes `text` to `path` through a temporary file in the same folder, then renames it.
pub fn write_atomically(path: &Path, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<(), Error> {
    let tmp = path.with_extension(format!(
        "{}.partial",
        path.extension()
            .map(|e| e.to_string_lossy().into_owned())
            .unwrap_or_default()
    ));
    let result = (|| {
        let file = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::with_capacity(1 << 16, file);
        fill(&mut w)?;
        w.flush()?;
        drop(w);
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, e)
    })
}

/// Writes a general unstructured grid.
pub fn write_vtu(
    path: &Path,
    points: &[[f64; 2]],
    cells: Cells<'_>,
    point_data: &[Field<'_>],
    cell_data: &[Field<'_>],
) -> Result<(), Error> {
    write_atomically(path, |w| write_vtu_to(w, points, cells, point_data, cell_data))
}

/// Writes the mesh as quadratic triangles with nodal fields.
pub fn write_mesh_vtu(
    path: &Path,
    mesh: &Mesh,
    point_data: &[Field<'_>],
    cell_data: &[Field<'_>],
) -> Result<(), Error> {
    let connectivity: Vec<usize> = mesh.triangles.iter().flatten().copied().collect();
    let cells = Cells {
        connectivity: &connectivity,
        nodes_per_cell: 6,
        vtk_type: VTK_QUADRATIC_TRIANGLE,
    };
    write_vtu(path, &mesh.nodes, cells, point_data, cell_data)
}

fn write_vtu_to(
    w: &mut dyn Write,
    points: &[[f64; 2]],
    cells: Cells<'_>,
    point_data: &[Field<'_>],
    cell_data: &[Field<'_>],
) -> std::io::Result<()> {
    let n_cells = cells.connectivity.len() / cells.nodes_per_cell.max(1);
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">"#
    )?;
    writeln!(w, "<UnstructuredGrid>")?;
    writeln!(
        w,
        r#"<Piece NumberOfPoints="{}" NumberOfCells="{}">"#,
        points.len(),
        n_cells
    )?;
    writeln!(w, "<Points>")?;
    writeln!(w, r#"<DataArray type="Float64" NumberOfComponents="3" format="ascii">"#)?;
    for p in points {
        writeln!(w, "{:e} {:e} 0", p[0], p[1])?;
    }
    writeln!(w, "</DataArray>\n</Points>")?;
    writeln!(w, "<Cells>")?;
    writeln!(w, r#"<DataArray type="Int64" Name="connectivity" format="ascii">"#)?;
    for c in cells.connectivity.chunks(cells.nodes_per_cell) {
        let line: Vec<String> = c.iter().map(|i| i.to_string()).collect();
        writeln!(w, "{}", line.join(" "))?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(w, r#"<DataArray type="Int64" Name="offsets" format="ascii">"#)?;
    for i in 1..=n_cells {
        writeln!(w, "{}", i * cells.nodes_per_cell)?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(w, r#"<DataArray type="UInt8" Name="types" format="ascii">"#)?;
    for _ in 0..n_cells {
        writeln!(w, "{}", cells.vtk_type)?;
    }
    writeln!(w, "</DataArray>\n</Cells>")?;
    if !point_data.is_empty() {
        writeln!(w, "<PointData>")?;
        for f in point_data {
            write_field(w, f)?;
        }
        writeln!(w, "</PointData>")?;
    }
    if !cell_data.is_empty() {
        writeln!(w, "<CellData>")?;
        for f in cell_data {
            write_field(w, f)?;
        }
        writeln!(w, "</CellData>")?;
    }
    writeln!(w, "</Piece>\n</UnstructuredGrid>\n</VTKFile>")?;
    Ok(())
}

fn write_field(w: &mut dyn Write, f: &Field<'_>) -> std::io::Result<()> {
    match f.data {
        FieldData::Scalar(v) => {
            writeln!(w, r#"<DataArray type="Float64" Name="{}" format="ascii">"#, f.name)?;
            for x in v {
                writeln!(w, "{x:e}")?;
            }
        }
        FieldData::Vector(v) => {
            // 3 components so ParaView can "Warp By Vector" directly.
            writeln!(
                w,
                r#"<DataArray type="Float64" Name="{}" NumberOfComponents="3" format="ascii">"#,
                f.name
            )?;
            for x in v {
                writeln!(w, "{:e} {:e} 0", x[0], x[1])?;
            }
        }
        FieldData::Tensor(v) => {
            // Full 3×3 (row-major), the layout ParaView shows as a tensor; zz = xz = yz = 0.
            writeln!(
                w,
                r#"<DataArray type="Float64" Name="{}" NumberOfComponents="9" format="ascii">"#,
                f.name
            )?;
            for s in v {
                writeln!(w, "{:e} {:e} 0 {:e} {:e} 0 0 0 0", s[0], s[2], s[2], s[1])?;
            }
        }
    }
    writeln!(w, "</DataArray>")
}
