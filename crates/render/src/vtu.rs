//! VTK XML unstructured grids (`.vtu`) for ParaView and meshio, zlib-compressed.
//!
//! **Layout.** Every data array is stored in one `<AppendedData encoding="raw">` section after the
//! XML header (`format="appended"`, `offset` counted from the byte after the leading `_`), compressed
//! the way VTK's `vtkZLibDataCompressor` writes it (`compressor="vtkZLibDataCompressor"`,
//! `header_type="UInt64"`): the array's little-endian bytes are cut into blocks of
//! [`BLOCK_SIZE`] bytes, each block is compressed on its own as a zlib stream, and the array starts
//! with the UInt64 header
//!
//! ```text
//! [number of blocks, BLOCK_SIZE, uncompressed size of the last block (0: a full block),
//!  compressed size of block 1, …, compressed size of block n]
//! ```
//!
//! followed by the compressed blocks. ParaView, VTK and meshio read it.
//!
//! **Geometry.** Points in 3-D with `z = 0`, connectivity and offsets as Int32. Six-node triangles are
//! `VTK_QUADRATIC_TRIANGLE` (type 22), whose node order (three corners, then the mid-edge nodes of
//! the edges 0→1, 1→2, 2→0) is exactly ours; three-node edges `VTK_QUADRATIC_EDGE` (type 21,
//! corners first, then the mid node). Several cell blocks of different types may follow each
//! other; cell data then runs over all cells in that order.
//!
//! **Values.** Float64 unless a field asks for Float32 ([`FieldData::Scalar32`],
//! [`FieldData::Tensor32`]); vectors get a zero `z` component (so that ParaView's "Warp By Vector"
//! applies directly) and symmetric 2-D tensors are written in VTK's six-component symmetric layout
//! `XX, YY, ZZ, XY, YZ, XZ` (named so in the file), which ParaView's tensor filters take as is.
//! Global values (time, angle) go to the grid's `<FieldData>` as one-tuple Float64 arrays.
//!
//! Files are written to a temporary name and renamed into place, so a crash never leaves a
//! half-written file under the final name.

use std::io::Write;
use std::path::Path;

use super::{Field, FieldData};
use crate::{Error, Mesh};
use pendulum_fem_core::store::write_atomically;

/// VTK cell type of the quadratic triangle.
pub const VTK_QUADRATIC_TRIANGLE: u8 = 22;
/// VTK cell type of the (linear) quadrilateral.
pub const VTK_QUAD: u8 = 9;
/// VTK cell type of the quadratic edge.
pub const VTK_QUADRATIC_EDGE: u8 = 21;
/// Uncompressed bytes per compressed block (VTK's default block size).
pub const BLOCK_SIZE: usize = 1 << 15;
/// zlib level 1, the fastest: Float64 values hardly compress, so a higher level saves few bytes for
/// much more writing time.
const ZLIB_LEVEL: u32 = 1;

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

impl Cells<'_> {
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.connectivity.len() / self.nodes_per_cell.max(1)
    }

    /// Whether there are no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Everything one `.vtu` file holds.
#[derive(Clone, Copy, Debug)]
pub struct Grid<'a> {
    /// Point coordinates \[m\].
    pub points: &'a [[f64; 2]],
    /// Cell blocks, written one after the other.
    pub cells: &'a [Cells<'a>],
    /// One value per point.
    pub point_data: &'a [Field<'a>],
    /// One value per cell (over all blocks, in order).
    pub cell_data: &'a [Field<'a>],
    /// Global values, `(name, value)`, e.g. `("TimeValue", 0.25)`.
    pub field_data: &'a [(&'a str, f64)],
}

/// Writes a general unstructured grid.
pub fn write_vtu(path: &Path, grid: &Grid<'_>) -> Result<(), Error> {
    let n_cells: usize = grid.cells.iter().map(Cells::len).sum();
    let n_points = grid.points.len();
    for (kind, fields, n) in [("point", grid.point_data, n_points), ("cell", grid.cell_data, n_cells)] {
        if let Some(f) = fields.iter().find(|f| f.data.len() != n) {
            return Err(Error::Input(format!(
                "{}: {kind} field `{}` has {} values for {n} {kind}s",
                path.display(),
                f.name,
                f.data.len()
            )));
        }
    }
    let arrays = arrays_of(grid);
    write_atomically(path, |w| write_vtu_to(w, grid, &arrays))
}

/// Writes the mesh as quadratic triangles with nodal fields.
pub fn write_mesh_vtu(
    path: &Path,
    mesh: &Mesh,
    point_data: &[Field<'_>],
    cell_data: &[Field<'_>],
) -> Result<(), Error> {
    let connectivity: Vec<usize> = mesh.triangles.iter().flatten().copied().collect();
    let cells = [Cells {
        connectivity: &connectivity,
        nodes_per_cell: 6,
        vtk_type: VTK_QUADRATIC_TRIANGLE,
    }];
    write_vtu(
        path,
        &Grid {
            points: &mesh.nodes,
            cells: &cells,
            point_data,
            cell_data,
            field_data: &[],
        },
    )
}

/// One data array: where it goes, its attributes and its compressed bytes.
struct Array {
    section: Section,
    name: String,
    vtk_type: &'static str,
    components: usize,
    /// A symmetric tensor: the file names its components.
    tensor: bool,
    compressed: Vec<u8>,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Section {
    Field,
    Points,
    Cells,
    PointData,
    CellData,
}

fn f64_bytes(values: impl Iterator<Item = f64>) -> Vec<u8> {
    values.flat_map(f64::to_le_bytes).collect()
}

fn f32_bytes(values: impl Iterator<Item = f64>) -> Vec<u8> {
    values.flat_map(|v| (v as f32).to_le_bytes()).collect()
}

fn i32_bytes(values: impl Iterator<Item = usize>) -> Vec<u8> {
    values
        .flat_map(|v| i32::try_from(v).expect("VTU index beyond Int32").to_le_bytes())
        .collect()
}

/// VTK's symmetric-tensor layout `[XX, YY, ZZ, XY, YZ, XZ]` of a 2-D tensor `[xx, yy, xy]`
/// (zz = yz = xz = 0).
fn symmetric_tensor(s: &[f64; 3]) -> [f64; 6] {
    [s[0], s[1], 0.0, s[2], 0.0, 0.0]
}

/// Component names of [`symmetric_tensor`], shown by ParaView.
const TENSOR_COMPONENTS: [&str; 6] = ["XX", "YY", "ZZ", "XY", "YZ", "XZ"];

/// Compresses `raw` in the `vtkZLibDataCompressor` layout (see the module documentation).
pub fn compress(raw: &[u8]) -> Vec<u8> {
    let blocks: Vec<Vec<u8>> = raw
        .chunks(BLOCK_SIZE)
        .map(|block| {
            let mut z = flate2::write::ZlibEncoder::new(
                Vec::with_capacity(block.len() / 2),
                flate2::Compression::new(ZLIB_LEVEL),
            );
            z.write_all(block).expect("writing to memory");
            z.finish().expect("writing to memory")
        })
        .collect();
    let mut out = Vec::with_capacity(8 * (3 + blocks.len()) + blocks.iter().map(Vec::len).sum::<usize>());
    out.extend_from_slice(&(blocks.len() as u64).to_le_bytes());
    out.extend_from_slice(&(BLOCK_SIZE as u64).to_le_bytes());
    out.extend_from_slice(&((raw.len() % BLOCK_SIZE) as u64).to_le_bytes());
    for b in &blocks {
        out.extend_from_slice(&(b.len() as u64).to_le_bytes());
    }
    for b in &blocks {
        out.extend_from_slice(b);
    }
    out
}

fn field_array(section: Section, f: &Field<'_>) -> Array {
    let (vtk_type, components, raw) = match f.data {
        FieldData::Scalar(v) => ("Float64", 1, f64_bytes(v.iter().copied())),
        FieldData::Scalar32(v) => ("Float32", 1, f32_bytes(v.iter().copied())),
        FieldData::Vector(v) => ("Float64", 3, f64_bytes(v.iter().flat_map(|x| [x[0], x[1], 0.0]))),
        FieldData::Tensor(v) => ("Float64", 6, f64_bytes(v.iter().flat_map(symmetric_tensor))),
        FieldData::Tensor32(v) => ("Float32", 6, f32_bytes(v.iter().flat_map(symmetric_tensor))),
        FieldData::Label(v) => ("UInt8", 1, v.to_vec()),
    };
    Array {
        section,
        name: f.name.to_string(),
        vtk_type,
        components,
        tensor: matches!(f.data, FieldData::Tensor(_) | FieldData::Tensor32(_)),
        compressed: compress(&raw),
    }
}

/// Every array of the grid, compressed, in the order they appear in the file.
fn arrays_of(grid: &Grid<'_>) -> Vec<Array> {
    let mut arrays = Vec::new();
    for (name, value) in grid.field_data {
        arrays.push(Array {
            section: Section::Field,
            name: name.to_string(),
            vtk_type: "Float64",
            components: 1,
            tensor: false,
            compressed: compress(&value.to_le_bytes()),
        });
    }
    arrays.push(Array {
        section: Section::Points,
        name: "Points".into(),
        vtk_type: "Float64",
        components: 3,
        tensor: false,
        compressed: compress(&f64_bytes(grid.points.iter().flat_map(|p| [p[0], p[1], 0.0]))),
    });
    let connectivity = grid.cells.iter().flat_map(|c| c.connectivity.iter().copied());
    let mut end = 0;
    let offsets = grid.cells.iter().flat_map(|c| {
        (0..c.len()).map(move |_| c.nodes_per_cell).map(move |n| {
            end += n;
            end
        })
    });
    let types: Vec<u8> = grid
        .cells
        .iter()
        .flat_map(|c| std::iter::repeat_n(c.vtk_type, c.len()))
        .collect();
    for (name, vtk_type, raw) in [
        ("connectivity", "Int32", i32_bytes(connectivity)),
        ("offsets", "Int32", i32_bytes(offsets)),
        ("types", "UInt8", types),
    ] {
        arrays.push(Array {
            section: Section::Cells,
            name: name.into(),
            vtk_type,
            components: 1,
            tensor: false,
            compressed: compress(&raw),
        });
    }
    arrays.extend(grid.point_data.iter().map(|f| field_array(Section::PointData, f)));
    arrays.extend(grid.cell_data.iter().map(|f| field_array(Section::CellData, f)));
    arrays
}

fn write_vtu_to(w: &mut dyn Write, grid: &Grid<'_>, arrays: &[Array]) -> std::io::Result<()> {
    let n_cells: usize = grid.cells.iter().map(Cells::len).sum();
    // offsets of the arrays in the appended section
    let mut offsets = Vec::with_capacity(arrays.len());
    let mut offset = 0;
    for a in arrays {
        offsets.push(offset);
        offset += a.compressed.len();
    }
    let tag = |w: &mut dyn Write, k: usize, extra: &str| -> std::io::Result<()> {
        let a = &arrays[k];
        let mut name = if a.section == Section::Points {
            String::new()
        } else {
            format!(r#" Name="{}""#, a.name)
        };
        if a.tensor {
            for (i, c) in TENSOR_COMPONENTS.iter().enumerate() {
                name.push_str(&format!(r#" ComponentName{i}="{c}""#));
            }
        }
        writeln!(
            w,
            r#"<DataArray type="{}"{name} NumberOfComponents="{}"{extra} format="appended" offset="{}"/>"#,
            a.vtk_type, a.components, offsets[k]
        )
    };
    let section = |w: &mut dyn Write, s: Section, open: &str, close: &str, extra: &str| -> std::io::Result<()> {
        let members: Vec<usize> = (0..arrays.len()).filter(|&k| arrays[k].section == s).collect();
        if members.is_empty() {
            return Ok(());
        }
        writeln!(w, "{open}")?;
        for k in members {
            tag(w, k, extra)?;
        }
        writeln!(w, "{close}")
    };
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64" compressor="vtkZLibDataCompressor">"#
    )?;
    writeln!(w, "<UnstructuredGrid>")?;
    section(
        w,
        Section::Field,
        "<FieldData>",
        "</FieldData>",
        r#" NumberOfTuples="1""#,
    )?;
    writeln!(
        w,
        r#"<Piece NumberOfPoints="{}" NumberOfCells="{n_cells}">"#,
        grid.points.len()
    )?;
    section(w, Section::Points, "<Points>", "</Points>", "")?;
    section(w, Section::Cells, "<Cells>", "</Cells>", "")?;
    section(w, Section::PointData, "<PointData>", "</PointData>", "")?;
    section(w, Section::CellData, "<CellData>", "</CellData>", "")?;
    writeln!(w, "</Piece>\n</UnstructuredGrid>")?;
    write!(w, "<AppendedData encoding=\"raw\">\n_")?;
    for a in arrays {
        w.write_all(&a.compressed)?;
    }
    writeln!(w, "\n</AppendedData>\n</VTKFile>")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    /// Undoes [`compress`]: checks the header and returns the raw bytes.
    fn decompress(data: &[u8]) -> Vec<u8> {
        let word = |k: usize| u64::from_le_bytes(data[8 * k..8 * k + 8].try_into().unwrap()) as usize;
        let (blocks, block_size, last) = (word(0), word(1), word(2));
        assert_eq!(block_size, BLOCK_SIZE);
        let mut at = 8 * (3 + blocks);
        let mut out = Vec::new();
        for b in 0..blocks {
            let size = word(3 + b);
            let mut raw = Vec::new();
            flate2::read::ZlibDecoder::new(&data[at..at + size])
                .read_to_end(&mut raw)
                .unwrap();
            let expected = if b + 1 == blocks && last != 0 { last } else { block_size };
            assert_eq!(raw.len(), expected, "block {b}");
            out.extend(raw);
            at += size;
        }
        assert_eq!(at, data.len(), "no bytes after the last block");
        out
    }

    #[test]
    fn compressed_blocks_round_trip_at_and_around_the_block_size() {
        for len in [1, 100, BLOCK_SIZE - 1, BLOCK_SIZE, BLOCK_SIZE + 1, 3 * BLOCK_SIZE + 17] {
            let raw: Vec<u8> = (0..len).map(|i| (i * 7919 % 251) as u8).collect();
            assert_eq!(decompress(&compress(&raw)), raw, "{len} bytes");
        }
    }

    #[test]
    fn appended_offsets_point_at_each_arrays_header() {
        let points = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]];
        let conn = [0, 1, 2, 3, 4, 5];
        let cells = [Cells {
            connectivity: &conn,
            nodes_per_cell: 6,
            vtk_type: VTK_QUADRATIC_TRIANGLE,
        }];
        let values = [1.5, -2.0, 3.25, 0.0, 1e-300, 7.0];
        let fields = [Field {
            name: "u_m",
            data: FieldData::Scalar(&values),
        }];
        let grid = Grid {
            points: &points,
            cells: &cells,
            point_data: &fields,
            cell_data: &[],
            field_data: &[("TimeValue", 0.125)],
        };
        let arrays = arrays_of(&grid);
        let mut bytes = Vec::new();
        write_vtu_to(&mut bytes, &grid, &arrays).unwrap();
        let start = bytes.windows(2).position(|w| w == b"\n_").unwrap() + 2;
        let text = String::from_utf8_lossy(&bytes[..start]);
        let offset_of = |name: &str| -> usize {
            let at = text.find(&format!(r#"Name="{name}""#)).unwrap();
            let rest = &text[at..];
            let o = rest.find("offset=\"").unwrap() + 8;
            rest[o..o + rest[o..].find('"').unwrap()].parse().unwrap()
        };
        let read = |offset: usize| {
            let data = &bytes[start + offset..];
            let blocks = u64::from_le_bytes(data[..8].try_into().unwrap()) as usize;
            let len: usize = (0..blocks)
                .map(|b| u64::from_le_bytes(data[24 + 8 * b..32 + 8 * b].try_into().unwrap()) as usize)
                .sum();
            decompress(&data[..8 * (3 + blocks) + len])
        };
        let time = read(offset_of("TimeValue"));
        assert_eq!(f64::from_le_bytes(time[..].try_into().unwrap()), 0.125);
        let u: Vec<f64> = read(offset_of("u_m"))
            .chunks(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(u, values, "bit-identical Float64");
        assert!(bytes.ends_with(b"\n</AppendedData>\n</VTKFile>\n"));
    }
}
