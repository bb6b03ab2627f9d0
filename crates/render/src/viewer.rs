//! `viewer.html`: one self-contained page that plays the swing in any browser, offline.
//!
//! The page (template `viewer.html` beside this file, compiled in) has no external scripts, styles, fonts or
//! network requests. It shows the deformed mesh (drawn like the animations, see [`super::anim`]:
//! rigid motion at true scale, elastic part magnified, each six-node triangle as four linear
//! sub-triangles with the colour interpolated), a colour bar in physical units, play/pause, a time
//! slider, a field selector and the θ(t) curve with a marker at the current time. The fields are
//! those of the animations, from the same values (`AnimField::values`): the elastic displacement
//! `|u − u_rigid|` (the part the picture magnifies, not the rigid swing) and the von Mises stress.
//!
//! Element ids (stable, for tests and scripts): `view` (mesh canvas), `theta-plot` (θ canvas),
//! `time-slider` (range input, one step per frame), `play` (button), `field` (select: `0` = the
//! elastic |u − u_rigid|, `1` = von Mises), `time-label`, `selftest`.
//!
//! ## Embedded data
//!
//! One JSON object in `<script id="pendulum-data" type="application/json">`:
//!
//! - `n_nodes`; `tris`: flat node indices of the linear sub-triangles; `boundary`: flat node pairs
//!   of the boundary segments; `bounds` `[xmin, ymin, xmax, ymax]` \[m\]; `wall_x` (or `null`);
//!   `magnification`, `magnification_label`;
//! - `fields`: `[{name, label, unit, max}]` for |u − u_rigid| \[m\] and von Mises \[Pa\];
//! - `frames`: per kept frame `{t, theta, step, pos, fields}`. `pos` is base64 of little-endian
//!   `int16` pairs `(qx, qy)` per node, the drawn position being `pos_offset + pos_scale · q` \[m\]
//!   (resolution: the picture size / 65534); `fields[k]` is base64 of little-endian `uint16` per
//!   node, value `= q / 65535 · fields[k].max`. This keeps the file about 11 bytes per node and frame.
//! - `theta_curve`: `{t, theta_deg}` from the run's history (the rows of `results.csv` and
//!   `impacts.csv`) when it has two records or more (at most 2000 points), else from the kept
//!   frames; `theta_max_deg` for the dashed ±θ_max lines.
//! - with a wall only: `wall` `{kind, face_x}` and `impacts` `[[start, end], …]` \[s\] (the
//!   history's, from the contact events of `events.csv`). The page draws the wall as a hatched
//!   band left of `wall_x` and the impacts as shaded spans with a line at each start in the θ plot.
//!
//! Loading the page with `#selftest` appended runs a check in the page itself: it hashes the
//! canvases, moves the slider and switches the field, counts the colour-map colours drawn over the
//! plate for each field on the first and the last frame (`plate_colours`), and writes the verdict
//! (`SELFTEST PASS` or `SELFTEST FAIL`) into `document.title` and the JSON details (including any
//! script errors and the decoded values of field 0 on the last frame, `last_frame_field0`) into
//! `#selftest`; `chromium --headless --dump-dom` prints it.

use std::path::Path;

use serde_json::json;

use super::anim::{field_max, AnimField, KeptFrame, Scene};
use super::base64;
use super::plot::History;
use super::raster;
use crate::{Error, Mesh};

const TEMPLATE: &str = include_str!("viewer.html");

/// The fields of the page, in the order of its selector: what `displacement.gif` and
/// `von_mises.gif` colour, each value per node from [`AnimField::values`].
const FIELDS: [AnimField; 2] = [AnimField::Displacement, AnimField::VonMises];

/// Writes `viewer.html` for `frames` (time order). `history`, if given, supplies the θ(t) curve.
pub fn write_viewer(
    path: &Path,
    mesh: &Mesh,
    frames: &[KeptFrame],
    scene: &Scene,
    history: Option<&History>,
    title: &str,
) -> Result<(), Error> {
    let html = viewer_html(mesh, frames, scene, history, title);
    pendulum_fem_core::store::write_atomically(path, |w| w.write_all(html.as_bytes()))
}

/// The page as a string (see [`write_viewer`]).
pub fn viewer_html(mesh: &Mesh, frames: &[KeptFrame], scene: &Scene, history: Option<&History>, title: &str) -> String {
    const SUB: [[usize; 3]; 4] = [[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]];
    let tris: Vec<usize> = mesh
        .triangles
        .iter()
        .flat_map(|t| SUB.iter().flat_map(move |s| s.map(|i| t[i])))
        .collect();
    let boundary: Vec<usize> = mesh
        .boundary_edges
        .iter()
        .flat_map(|e| [e.nodes[0], e.nodes[2], e.nodes[2], e.nodes[1]])
        .collect();
    let [x0, y0, x1, y1] = scene.bounds;
    let offset = [0.5 * (x0 + x1), 0.5 * (y0 + y1)];
    let pos_scale = (0.5 * (x1 - x0)).max(0.5 * (y1 - y0)).max(1e-300) / 32767.0;
    let maxima = FIELDS.map(|field| field_max(frames, field));

    let frames_json: Vec<serde_json::Value> = frames
        .iter()
        .map(|f| {
            let mut pos = Vec::with_capacity(4 * f.elastic.len());
            for p in f.drawn_positions(&mesh.nodes, scene.magnification) {
                for k in 0..2 {
                    let q = ((p[k] - offset[k]) / pos_scale).round().clamp(-32767.0, 32767.0) as i16;
                    pos.extend_from_slice(&q.to_le_bytes());
                }
            }
            let fields: Vec<String> = FIELDS
                .iter()
                .zip(maxima)
                .map(|(field, max)| {
                    let v = field.values(f);
                    let mut b = Vec::with_capacity(2 * v.len());
                    for &x in v {
                        let q = (x as f64 / max * 65535.0).round().clamp(0.0, 65535.0) as u16;
                        b.extend_from_slice(&q.to_le_bytes());
                    }
                    base64(&b)
                })
                .collect();
            json!({
                "t": f.time,
                "theta": f.theta,
                "step": f.step,
                "pos": base64(&pos),
                "fields": fields,
            })
        })
        .collect();

    let (curve_t, curve_theta): (Vec<f64>, Vec<f64>) = match history.filter(|h| h.time.len() >= 2) {
        Some(h) => {
            let stride = h.time.len().div_ceil(2000).max(1);
            let mut idx: Vec<usize> = (0..h.time.len()).step_by(stride).collect();
            if idx.last() != Some(&(h.time.len() - 1)) {
                idx.push(h.time.len() - 1);
            }
            idx.iter().map(|&i| (h.time[i], h.theta[i].to_degrees())).unzip()
        }
        None => frames.iter().map(|f| (f.time, f.theta.to_degrees())).unzip(),
    };
    let first = curve_theta.first().copied().unwrap_or(0.0).abs();
    let theta_max = if first > 1e-9 {
        first
    } else {
        curve_theta.iter().fold(0.0f64, |a, v| a.max(v.abs()))
    };

    let mag_label = raster::two_digits(scene.magnification);
    let data = json!({
        "title": title,
        "info": format!(
            "{} frames, {} six-node triangles. The swing is drawn at true scale; only the elastic part of the \
             displacement (u minus the rigid rotation by \u{3b8}) is magnified \u{d7} {mag_label}. Colour scales \
             run from 0 to the largest value over all frames. Dashed lines in the \u{3b8} plot: \u{b1}\u{3b8}_max = \
             \u{b1}{theta_max:.2}\u{b0}.",
            frames.len(),
            mesh.triangles.len()
        ),
        "n_nodes": mesh.nodes.len(),
        "tris": tris,
        "boundary": boundary,
        "bounds": scene.bounds,
        "wall_x": scene.wall_x,
        "magnification": scene.magnification,
        "magnification_label": mag_label,
        "pos_offset": offset,
        "pos_scale": pos_scale,
        "fields": [
            {"name": "|u − u_rigid|", "label": AnimField::Displacement.bar_title(), "unit": "m", "max": maxima[0]},
            {"name": "von Mises", "label": AnimField::VonMises.bar_title(), "unit": "Pa", "max": maxima[1]},
        ],
        "frames": frames_json,
        "theta_curve": {"t": curve_t, "theta_deg": curve_theta},
        "theta_max_deg": theta_max,
    });
    let mut data = data;
    // with a wall: its face (drawn as a band, see `wall_x`) and the impacts for the θ plot
    if let (Some(x), Some(obj)) = (scene.wall_x, data.as_object_mut()) {
        let impacts: Vec<[f64; 2]> = history
            .map(|h| h.impacts.iter().map(|&(a, b)| [a, b]).collect())
            .unwrap_or_default();
        obj.insert("wall".into(), json!({"kind": "half-plane x <= face_x", "face_x": x}));
        obj.insert("impacts".into(), json!(impacts));
    }
    // `</` must not appear inside a <script> element.
    let text = data.to_string().replace("</", "<\\/");
    TEMPLATE.replacen("/*DATA*/", &text, 1)
}
