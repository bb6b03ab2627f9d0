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
//! **With a wall** ([`PvdWriter::set_wall`]) every frame also has the point field
//! `contact_pressure_Pa` (`k · max(−gap, 0)` on the head's contact boundary, 0 elsewhere), and the
//! wall is a second block: `wall.vtu` (one quad over the wall's block, cell field `wall`, field
//! data `face_x`) is listed as `part="1"` of every time step, so ParaView's PVD reader shows each
//! time step as a multiblock of the bodies' mesh (part 0) and the rigid wall (part 1). Without a
//! wall the files are as before.
//!
//! The `.pvd` is rewritten atomically after every frame (it is a few dozen bytes per entry), so it
//! is valid and lists exactly the frames on disk whenever the run stops. Step numbers in file names
//! have at least five digits (`step_00042.vtu`).

use std::io::Write;
use std::path::{Path, PathBuf};

use super::{vtu, Field, FieldData, Frame};
use crate::wall::WallOutput;
use crate::{Error, Mesh};

pub use pendulum_fem_run::outdir::names::FRAMES_DIR;
pub use pendulum_fem_run::outdir::names::PVD_NAME;

/// Streams frames to VTU files and keeps `pendulum.pvd` up to date.
#[derive(Debug)]
pub struct PvdWriter {
    dir: PathBuf,
    /// `(time, relative file name)` of every frame written.
    entries: Vec<(f64, String)>,
    written: Vec<PathBuf>,
    /// The rigid wall, when the run has one: `wall.vtu` is listed as part 1 of every time step
    /// and the frames carry `contact_pressure_Pa`.
    wall: Option<WallOutput>,
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
            wall: None,
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
            wall: None,
        };
        w.write_pvd()?;
        Ok(w)
    }

    /// Adds the wall: a rigid one (see [`WallOutput::rigid`]) writes `wall.vtu` (the block [`WallOutput::extent`] as one quad),
    /// lists it as part 1 of every time step of the `.pvd` (ParaView shows the two parts as the
    /// blocks of a multiblock data set), and gives every frame the point field
    /// `contact_pressure_Pa` (see [`WallOutput::pressure`]).
    pub fn set_wall(&mut self, wall: WallOutput) -> Result<(), Error> {
        if wall.rigid {
            let path = self.dir.join(WALL_VTU);
            write_wall_vtu(&path, &wall)?;
            if !self.written.contains(&path) {
                self.written.push(path);
            }
        }
        self.wall = Some(wall);
        self.write_pvd()
    }

    /// Path of the collection file.
    pub fn pvd_path(&self) -> PathBuf {
        self.dir.join(PVD_NAME)
    }

    /// Writes `frames/step_NNNNN.vtu` for this frame and rewrites the `.pvd`.
    pub fn write_frame(&mut self, mesh: &Mesh, frame: &Frame<'_>) -> Result<(), Error> {
        let rel = format!("{FRAMES_DIR}/step_{:05}.vtu", frame.step);
        let path = self.dir.join(&rel);
        match &self.wall {
            Some(wall) => {
                let pressure = wall.pressure(mesh, frame.displacement);
                let extra = [Field {
                    name: arrays::CONTACT_PRESSURE,
                    data: FieldData::Scalar(&pressure),
                }];
                write_frame_vtu_with(&path, mesh, frame, &extra)?;
            }
            None => write_frame_vtu(&path, mesh, frame)?,
        }
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
        let wall = self.wall.as_ref().filter(|w| w.rigid).map(|_| WALL_VTU);
        pendulum_fem_core::store::write_atomically(&self.pvd_path(), |w| write_pvd_to(w, &self.entries, wall))
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
    /// Contact pressure on the head's boundary \[Pa\] (runs with a wall).
    pub const CONTACT_PRESSURE: &str = "contact_pressure_Pa";
    /// Prefix of the cell flags of the named boundaries (`boundary_rotation`, …).
    pub const BOUNDARY_PREFIX: &str = "boundary_";
}

/// The size of one frame file of `mesh` \[bytes\], estimated: 80 bytes per node (the Float64
/// points and kinematic fields hardly compress; the Float32 stresses), 16 per triangle
/// (connectivity and offsets, compressed) and 4 kB of header.
pub fn estimated_frame_bytes(mesh: &Mesh) -> u64 {
    80 * mesh.num_nodes() as u64 + 16 * mesh.triangles.len() as u64 + 4000
}

/// Writes one frame: the triangles, then the named boundary edges as quadratic edge cells, the
/// nodal fields, one cell flag per boundary name, and `TimeValue`, `theta_rad` and `step` as field
/// data.
pub fn write_frame_vtu(path: &Path, mesh: &Mesh, frame: &Frame<'_>) -> Result<(), Error> {
    write_frame_vtu_with(path, mesh, frame, &[])
}

/// [`write_frame_vtu`] with further point fields after the frame's own.
pub fn write_frame_vtu_with(path: &Path, mesh: &Mesh, frame: &Frame<'_>, extra: &[Field<'_>]) -> Result<(), Error> {
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
    let mut point_data = vec![
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
    point_data.extend(extra.iter().map(|f| Field {
        name: f.name,
        data: f.data,
    }));
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

/// File name of the rigid wall's block, next to the `.pvd`.
pub const WALL_VTU: &str = "wall.vtu";

/// Writes the wall's block: one quad over [`WallOutput::extent`], with the cell field `wall` = 1.
fn write_wall_vtu(path: &Path, wall: &WallOutput) -> Result<(), Error> {
    let [x0, y0, x1, y1] = wall.extent;
    let points = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
    let quad = [0, 1, 2, 3];
    let cells = [vtu::Cells {
        connectivity: &quad,
        nodes_per_cell: 4,
        vtk_type: vtu::VTK_QUAD,
    }];
    let one = [1u8];
    vtu::write_vtu(
        path,
        &vtu::Grid {
            points: &points,
            cells: &cells,
            point_data: &[],
            cell_data: &[Field {
                name: "wall",
                data: FieldData::Label(&one),
            }],
            field_data: &[("face_x", wall.face_x)],
        },
    )
}

fn write_pvd_to(w: &mut dyn Write, entries: &[(f64, String)], wall: Option<&str>) -> std::io::Result<()> {
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">"#
    )?;
    writeln!(w, "<Collection>")?;
    for (t, file) in entries {
        // `{:?}` of f64 is the shortest string that reads back to the same value.
        writeln!(w, r#"<DataSet timestep="{t:?}" group="" part="0" file="{file}"/>"#)?;
        if let Some(wall) = wall {
            writeln!(w, r#"<DataSet timestep="{t:?}" group="" part="1" file="{wall}"/>"#)?;
        }
    }
    writeln!(w, "</Collection>")?;
    writeln!(w, "</VTKFile>")
}
