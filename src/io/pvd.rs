//! ParaView time series: one `frames/step_NNNNN.vtu` per written step and a `pendulum.pvd`
//! collection that lists them with their times.
//!
//! Each frame is written as soon as it arrives ([`PvdWriter::write_frame`]) and nothing of it is
//! kept. The VTU files hold the mesh as quadratic triangles (see [`super::vtu`]) with the point
//! data `displacement`, `velocity`, `acceleration` (vectors), `von_mises` (scalar) and
//! `cauchy_stress` (a full 3×3 tensor with zero out-of-plane components). ParaView's
//! "Warp By Vector" on `displacement` shows the deformed pendulum.
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

    /// Path of the collection file.
    pub fn pvd_path(&self) -> PathBuf {
        self.dir.join(PVD_NAME)
    }

    /// Writes `frames/step_NNNNN.vtu` for this frame and rewrites the `.pvd`.
    pub fn write_frame(&mut self, mesh: &Mesh, frame: &Frame<'_>) -> Result<(), Error> {
        let rel = format!("{FRAMES_DIR}/step_{:05}.vtu", frame.step);
        let path = self.dir.join(&rel);
        let point_data = [
            Field {
                name: "displacement",
                data: FieldData::Vector(frame.displacement),
            },
            Field {
                name: "velocity",
                data: FieldData::Vector(frame.velocity),
            },
            Field {
                name: "acceleration",
                data: FieldData::Vector(frame.acceleration),
            },
            Field {
                name: "von_mises",
                data: FieldData::Scalar(frame.von_mises),
            },
            Field {
                name: "cauchy_stress",
                data: FieldData::Tensor(frame.cauchy),
            },
        ];
        vtu::write_mesh_vtu(&path, mesh, &point_data, &[])?;
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
