//! ParaView time series: one `frames/step_NNNNN.vtu` per written step and a `pendulum.pvd`
//! collection that lists them with their times.
//!
//! Each frame is written as soon as it arrives ([`PvdWriter::write_frame`]) and nothing of it is
//! kept. The VTU files (compressed, see [`super::vtu`]) hold the mesh as quadratic triangles
//! followed by the named boundary edges as quadratic edge cells, with the point data
//! `displacement_m`, `velocity_m_s`, `acceleration_m_s2` (Float64 vectors), `von_mises_Pa` and
//! `cauchy_stress_Pa` (Float32; the tensor in VTK's symmetric six-component layout, out-of-plane
//! components zero), one UInt8 cell flag per boundary name (`boundary_rotation`, … : 1 on that
//! boundary's edges, 0 elsewhere) and the field data `TimeValue` \[s\], `theta_rad` and `step`.
//! ParaView's "Warp By Vector" on `displacement_m` shows the deformed pendulum; "Threshold" on a
//! boundary flag picks that boundary. The stresses are Float32 because seven significant digits are
//! far finer than the error of the nodal stress recovery; the kinematic fields need Float64 (the
//! elastic part of the displacement is 1e-8 of the rigid part for steel).
//!
//! The `.pvd` is rewritten atomically after every frame (it is a few dozen bytes per entry), so it
//! is valid and lists exactly the frames on disk whenever the run stops. Step numbers in file names
//! have at least five digits (`step_00042.vtu`).

use std::io::Write;
use std::path::{Path, PathBuf};

use super::{vtu, Field, FieldData, Frame};
use crate::{Error, Mesh};

/// Name of the collection file.
pub const PVD_NAME: &str = "pendulum.pvd";
/// Folder of the frame files, relative to the output folder.
pub const FRAMES_DIR: &str = "frames";

/// Streams frames to VTU files and keeps `pendulum.pvd` up to date.
#[derive(Debug)]
pub struct PvdWriter {
    dir: PathBuf,
    /// `(time, relative file name)` of every frame written.
    entries: Vec<(f64, String)>,
    written: Vec<PathBuf>,
}

impl PvdWriter {
    /// Creates `dir/frames/` and writes an empty, valid `dir/pendulum.pvd`.
    pub fn new(dir: &Path) -> Result<Self, Error> {
        let frames = dir.join(FRAMES_DIR);
        std::fs::create_dir_all(&frames).map_err(|e| Error::io(&frames, e))?;
        let w = Self {
            dir: dir.to_path_buf(),
            entries: Vec::new(),
            written: Vec::new(),
        };
        w.write_pvd()?;
        Ok(w)
    }

    /// Continues a collection in `dir` with the frames `entries` (`(time, relative file name)`)
    /// of an earlier, restarted run; rewrites `dir/pendulum.pvd` with them.
    pub fn resume(dir: &Path, entries: Vec<(f64, String)>) -> Result<Self, Error> {
        let frames = dir.join(FRAMES_DIR);
        std::fs::create_dir_all(&frames).map_err(|e| Error::io(&frames, e))?;
        let w = Self {
            dir: dir.to_path_buf(),
            written: entries.iter().map(|(_, rel)| dir.join(rel)).collect(),
            entries,
        };
        w.write_pvd()?;
        Ok(w)
    }

    /// Path of the collection file.
    pub fn pvd_path(&self) -> PathBuf {
        self.dir.join(PVD_NAME)
    }

    /// Writes `frames/step_NNNNN.vtu` for this frame and rewrites the `.pvd`.
    pub fn write_frame(&mut self, mesh: &Mesh, frame: &Frame<'_>) -> Result<(), Error> {
        let rel = format!("{FRAMES_DIR}/step_{:05}.vtu", frame.step);
        let path = self.dir.join(&rel);
        write_frame_vtu(&path, mesh, frame)?;
        self.entries.push((frame.time, rel));
        self.written.push(path);
        self.write_pvd()
    }

    /// Every file written so far (VTU files; the `.pvd` itself is [`PvdWriter::pvd_path`]).
    pub fn written(&self) -> &[PathBuf] {
        &self.written
    }

    /// Consumes the writer: all VTU paths and the `.pvd` path.
    pub fn into_paths(self) -> Vec<PathBuf> {
        let pvd = self.pvd_path();
        let mut v = self.written;
        v.push(pvd);
        v
    }

    fn write_pvd(&self) -> Result<(), Error> {
        vtu::write_atomically(&self.pvd_path(), |w| write_pvd_to(w, &self.entries))
    }
}

/// Names of the nodal arrays of a frame, with their units.
pub mod arrays {
    /// Displacement \[m\].
    pub const DISPLACEMENT: &str = "displacement_m";
    /// Velocity \[m/s\].
    pub const VELOCITY: &str = "velocity_m_s";
    /// Acceleration \[m/s²\].
    pub const ACCELERATION: &str = "acceleration_m_s2";
    /// Von Mises stress \[Pa\].
    pub const VON_MISES: &str = "von_mises_Pa";
    /// Cauchy stress \[Pa\].
    pub const CAUCHY: &str = "cauchy_stress_Pa";
    /// Prefix of the cell flags of the named boundaries (`boundary_rotation`, …).
    pub const BOUNDARY_PREFIX: &str = "boundary_";
}

/// The size of one frame file of `mesh` \[bytes\], estimated: 80 bytes per node (the Float64
/// points and kinematic fields hardly compress; the Float32 stresses), 16 per triangle
/// (connectivity and offsets, compressed) and 4 kB of header. The default run's frames (2727
/// nodes, 1233 triangles) measure 200 to 243 kB against the estimated 242 kB.
pub fn estimated_frame_bytes(mesh: &Mesh) -> u64 {
    80 * mesh.num_nodes() as u64 + 16 * mesh.triangles.len() as u64 + 4000
}

/// Writes one frame: the triangles, then the named boundary edges as quadratic edge cells, the
/// nodal fields, one cell flag per boundary name, and `TimeValue`, `theta_rad` and `step` as field
/// data.
pub fn write_frame_vtu(path: &Path, mesh: &Mesh, frame: &Frame<'_>) -> Result<(), Error> {
    let triangles: Vec<usize> = mesh.triangles.iter().flatten().copied().collect();
    let edges: Vec<usize> = mesh.boundary_edges.iter().flat_map(|e| e.nodes).collect();
    let cells = [
        vtu::Cells {
            connectivity: &triangles,
            nodes_per_cell: 6,
            vtk_type: vtu::VTK_QUADRATIC_TRIANGLE,
        },
        vtu::Cells {
            connectivity: &edges,
            nodes_per_cell: 3,
            vtk_type: vtu::VTK_QUADRATIC_EDGE,
        },
    ];
    let flags: Vec<(String, Vec<u8>)> = (0..mesh.boundary_names.len())
        .map(|id| {
            let name = format!("{}{}", arrays::BOUNDARY_PREFIX, mesh.boundary_names[id]);
            let values = std::iter::repeat_n(0, mesh.triangles.len())
                .chain(mesh.boundary_edges.iter().map(|e| u8::from(e.name == id)))
                .collect();
            (name, values)
        })
        .collect();
    let cell_data: Vec<Field<'_>> = flags
        .iter()
        .map(|(name, values)| Field {
            name,
            data: FieldData::Label(values),
        })
        .collect();
    let point_data = [
        Field {
            name: arrays::DISPLACEMENT,
            data: FieldData::Vector(frame.displacement),
        },
        Field {
            name: arrays::VELOCITY,
            data: FieldData::Vector(frame.velocity),
        },
        Field {
            name: arrays::ACCELERATION,
            data: FieldData::Vector(frame.acceleration),
        },
        Field {
            name: arrays::VON_MISES,
            data: FieldData::Scalar32(frame.von_mises),
        },
        Field {
            name: arrays::CAUCHY,
            data: FieldData::Tensor32(frame.cauchy),
        },
    ];
    vtu::write_vtu(
        path,
        &vtu::Grid {
            points: &mesh.nodes,
            cells: &cells,
            point_data: &point_data,
            cell_data: &cell_data,
            field_data: &[
                ("TimeValue", frame.time),
                ("theta_rad", frame.theta),
                ("step", frame.step as f64),
            ],
        },
    )
}

fn write_pvd_to(w: &mut dyn Write, entries: &[(f64, String)]) -> std::io::Result<()> {
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">"#
    )?;
    writeln!(w, "<Collection>")?;
    for (t, file) in entries {
        // `{:?}` of f64 is the shortest string that reads back to the same value.
        writeln!(w, r#"<DataSet timestep="{t:?}" group="" part="0" file="{file}"/>"#)?;
    }
    writeln!(w, "</Collection>")?;
    writeln!(w, "</VTKFile>")
}
