//! VTK XML unstructured grids (`.vtu`) for ParaView and meshio.
//!
//! Inline binary format (`format="binary"`: base64 of a UInt64 byte count followed by the
//! little-endian values, uncompressed), which ParaView, VTK and meshio read; points in 3-D with
//! `z = 0`. Six-node triangles are written as
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

/// Base64 of the VTK inline binary block: UInt64 byte count, then the raw little-endian values.
fn binary_block<T: Copy>(values: impl Iterator<Item = T>, to_bytes: impl Fn(T) -> [u8; 8]) -> String {
    let mut bytes = vec![0u8; 8];
    for v in values {
        bytes.extend_from_slice(&to_bytes(v));
    }
    let len = (bytes.len() - 8) as u64;
    bytes[..8].copy_from_slice(&len.to_le_bytes());
    super::base64(&bytes)
}

fn f64_block(values: impl Iterator<Item = f64>) -> String {
    binary_block(values, f64::to_le_bytes)
}

fn i64_block(values: impl Iterator<Item = usize>) -> String {
    binary_block(values, |v| (v as i64).to_le_bytes())
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
    writeln!(
        w,
        r#"<DataArray type="Float64" NumberOfComponents="3" format="binary">"#
    )?;
    writeln!(w, "{}", f64_block(points.iter().flat_map(|p| [p[0], p[1], 0.0])))?;
    writeln!(w, "</DataArray>\n</Points>")?;
    writeln!(w, "<Cells>")?;
    writeln!(w, r#"<DataArray type="Int64" Name="connectivity" format="binary">"#)?;
    writeln!(w, "{}", i64_block(cells.connectivity.iter().copied()))?;
    writeln!(w, "</DataArray>")?;
    writeln!(w, r#"<DataArray type="Int64" Name="offsets" format="binary">"#)?;
    writeln!(w, "{}", i64_block((1..=n_cells).map(|i| i * cells.nodes_per_cell)))?;
    writeln!(w, "</DataArray>")?;
    // types are one byte each: their own block
    let mut types = vec![0u8; 8];
    types.extend(std::iter::repeat_n(cells.vtk_type, n_cells));
    types[..8].copy_from_slice(&(n_cells as u64).to_le_bytes());
    writeln!(w, r#"<DataArray type="UInt8" Name="types" format="binary">"#)?;
    writeln!(w, "{}", super::base64(&types))?;
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
    let (components, block) = match f.data {
        FieldData::Scalar(v) => (1, f64_block(v.iter().copied())),
        // 3 components so ParaView can "Warp By Vector" directly.
        FieldData::Vector(v) => (3, f64_block(v.iter().flat_map(|x| [x[0], x[1], 0.0]))),
        // Full 3×3 (row-major), the layout ParaView shows as a tensor; zz = xz = yz = 0.
        FieldData::Tensor(v) => (
            9,
            f64_block(v.iter().flat_map(|s| [s[0], s[2], 0.0, s[2], s[1], 0.0, 0.0, 0.0, 0.0])),
        ),
    };
    writeln!(
        w,
        r#"<DataArray type="Float64" Name="{}" NumberOfComponents="{components}" format="binary">"#,
        f.name
    )?;
    writeln!(w, "{block}")?;
    writeln!(w, "</DataArray>")
}
