//! The files of a modal analysis (`pendulum-fem modes`): the mode shapes for ParaView and a
//! picture of the first ones.
//!
//! * `modes.pvd` lists `modes/mode_NN.vtu`, one file per mode with the mode number as its
//!   "time" (ParaView's time slider steps through the modes). Each holds the mesh as quadratic
//!   triangles and the point field `displacement_m`, the mass-normalised shape `φ` scaled so that
//!   its largest nodal displacement is [`SHAPE_SCALE`] of the body's largest distance from the
//!   pivot (a shape's amplitude is arbitrary; "Warp By Vector" with factor 1 then shows a visible
//!   deformation), and the field data `mode`, `omega2_rad2_s2`, `frequency_Hz` and `scale`
//!   (the factor applied to the `M`-orthonormal shape).
//! * `modes.png`: the first modes (up to [`PICTURE_MODES`]) side by side, each deformed by its
//!   scaled shape over the undeformed outline (grey), titled with its number and frequency.

use std::path::{Path, PathBuf};

use pendulum_fem_run::outdir::names;
use plotters::prelude::*;

use super::plot::{render_png, DrawResult, Root};
use super::{vtu, Field, FieldData};
use crate::{Error, Mesh};

/// Largest nodal displacement of a written or drawn shape, as a fraction of the body's size.
pub const SHAPE_SCALE: f64 = 0.1;

/// Modes drawn in `modes.png` at most.
pub const PICTURE_MODES: usize = 6;

/// One mode to write or draw.
#[derive(Clone, Copy, Debug)]
pub struct ModeView<'a> {
    /// Mode number shown (0 for the rigid rotation).
    pub number: usize,
    /// `ω²` \[rad²/s²\].
    pub omega2: f64,
    /// Frequency \[Hz\].
    pub frequency_hz: f64,
    /// Interleaved nodal shape (any normalisation).
    pub shape: &'a [f64],
}

/// The largest distance of a node from the origin (the pivot) \[m\].
fn body_size(mesh: &Mesh) -> f64 {
    mesh.nodes.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max)
}

/// The factor that makes the largest nodal displacement of `shape` [`SHAPE_SCALE`] of the body.
pub fn display_scale(mesh: &Mesh, shape: &[f64]) -> f64 {
    let largest = shape.chunks_exact(2).map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
    if largest > 0.0 {
        SHAPE_SCALE * body_size(mesh) / largest
    } else {
        0.0
    }
}

/// Writes `dir/modes/mode_NN.vtu` for every mode and `dir/modes.pvd`; returns the files.
pub fn write_modes_pvd(dir: &Path, mesh: &Mesh, modes: &[ModeView<'_>]) -> Result<Vec<PathBuf>, Error> {
    let sub = dir.join(names::MODES_DIR);
    std::fs::create_dir_all(&sub).map_err(|e| Error::io(&sub, e))?;
    let mut written = Vec::new();
    let mut entries = Vec::new();
    for m in modes {
        let scale = display_scale(mesh, m.shape);
        let disp: Vec<[f64; 2]> = m.shape.chunks_exact(2).map(|p| [scale * p[0], scale * p[1]]).collect();
        let name = format!("mode_{:02}.vtu", m.number);
        let path = sub.join(&name);
        let connectivity: Vec<usize> = mesh.triangles.iter().flatten().copied().collect();
        let cells = [vtu::Cells {
            connectivity: &connectivity,
            nodes_per_cell: 6,
            vtk_type: vtu::VTK_QUADRATIC_TRIANGLE,
        }];
        let point_data = [Field {
            name: "displacement_m",
            data: FieldData::Vector(&disp),
        }];
        let field_data = [
            ("mode", m.number as f64),
            ("omega2_rad2_s2", m.omega2),
            ("frequency_Hz", m.frequency_hz),
            ("scale", scale),
        ];
        vtu::write_vtu(
            &path,
            &vtu::Grid {
                points: &mesh.nodes,
                cells: &cells,
                point_data: &point_data,
                cell_data: &[],
                field_data: &field_data,
            },
        )?;
        written.push(path);
        entries.push((m.number, format!("{}/{name}", names::MODES_DIR)));
    }
    let pvd = dir.join(names::MODES_PVD);
    pendulum_fem_core::store::write_atomically(&pvd, |w| {
        writeln!(w, r#"<?xml version="1.0"?>"#)?;
        writeln!(
            w,
            r#"<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">"#
        )?;
        writeln!(w, "<Collection>")?;
        for (number, file) in &entries {
            writeln!(w, r#"<DataSet timestep="{number}" group="" part="0" file="{file}"/>"#)?;
        }
        writeln!(w, "</Collection>")?;
        writeln!(w, "</VTKFile>")
    })?;
    written.push(pvd);
    Ok(written)
}

/// Size of one panel of `modes.png` \[px\].
const PANEL: (u32, u32) = (300, 520);

/// Writes `modes.png`: the first [`PICTURE_MODES`] modes side by side (see the module doc).
pub fn write_modes_png(path: &Path, mesh: &Mesh, modes: &[ModeView<'_>]) -> Result<(), Error> {
    let shown = &modes[..modes.len().min(PICTURE_MODES)];
    let columns = shown.len().clamp(1, 3) as u32;
    let rows = shown.len().div_ceil(3).max(1) as u32;
    let size = (PANEL.0 * columns, PANEL.1 * rows);
    render_png(path, size, |root| draw(root, mesh, shown, columns as usize))
}

fn draw(root: &Root<'_>, mesh: &Mesh, modes: &[ModeView<'_>], columns: usize) -> DrawResult {
    let rows = modes.len().div_ceil(columns).max(1);
    let panels = root.split_evenly((rows, columns));
    // a common frame around the undeformed body, padded for the deformation
    let pad = 1.6 * SHAPE_SCALE * body_size(mesh);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &mesh.nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let (x0, x1, y0, y1) = (lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad);
    // equal scales: widen the narrower range to the panel's aspect ratio
    let aspect = (PANEL.0 as f64 - 20.0) / (PANEL.1 as f64 - 50.0);
    let (w, h) = (x1 - x0, y1 - y0);
    let (xm, ym) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let (w, h) = if w / h < aspect {
        (h * aspect, h)
    } else {
        (w, w / aspect)
    };
    let xr = (xm - 0.5 * w)..(xm + 0.5 * w);
    let yr = (ym - 0.5 * h)..(ym + 0.5 * h);
    let undeformed = RGBColor(170, 170, 170);
    let edges_color = RGBColor(120, 160, 215);
    let outline = RGBColor(20, 60, 150);
    for (panel, m) in panels.iter().zip(modes) {
        let title = if m.frequency_hz < 1e-6 * (m.omega2.abs().sqrt() + 1.0) || m.number == 0 {
            format!("mode {}: rigid, 0 Hz", m.number)
        } else {
            format!("mode {}: {:.1} Hz", m.number, m.frequency_hz)
        };
        let mut chart = ChartBuilder::on(panel)
            .caption(title, ("sans-serif", 18))
            .margin(10)
            .build_cartesian_2d(xr.clone(), yr.clone())?;
        let scale = display_scale(mesh, m.shape);
        let at = |n: usize, s: f64| {
            (
                mesh.nodes[n][0] + s * m.shape[2 * n],
                mesh.nodes[n][1] + s * m.shape[2 * n + 1],
            )
        };
        let boundary = |s: f64| -> Vec<Vec<(f64, f64)>> {
            mesh.boundary_edges
                .iter()
                .map(|e| vec![at(e.nodes[0], s), at(e.nodes[2], s), at(e.nodes[1], s)])
                .collect()
        };
        // the undeformed outline in grey, the deformed body's element edges (each through its
        // mid node) and outline on top
        for pts in boundary(0.0) {
            chart.draw_series(std::iter::once(PathElement::new(pts, undeformed.stroke_width(2))))?;
        }
        for tri in &mesh.triangles {
            for (a, mid, b) in [(0, 3, 1), (1, 4, 2), (2, 5, 0)] {
                let pts = vec![at(tri[a], scale), at(tri[mid], scale), at(tri[b], scale)];
                chart.draw_series(std::iter::once(PathElement::new(pts, edges_color.stroke_width(1))))?;
            }
        }
        for pts in boundary(scale) {
            chart.draw_series(std::iter::once(PathElement::new(pts, outline.stroke_width(2))))?;
        }
        // the pivot
        chart.draw_series(std::iter::once(Circle::new((0.0, 0.0), 4, BLACK.filled())))?;
    }
    Ok(())
}
