//! What every frame of an animation shares and draws the same: the field shown and its scale, the
//! scene (magnification, viewport, wall), the map from metres to pixels and the frame template
//! (titles, caption, colour bar, the wall band).

use super::kept::{auto_magnification, KeptFrame};
use crate::font::Text;
use crate::raster::{self, Anchor, Canvas, BLACK, GREY, LIGHT_GREY, WHITE};

/// Which field an animation shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnimField {
    /// The magnitude of the elastic displacement \[m\] ([`KeptFrame::elastic_abs`]).
    Displacement,
    /// Von Mises stress \[Pa\].
    VonMises,
}

impl AnimField {
    /// The field's value per node of `f`: the one definition the animations and the viewer colour.
    pub(crate) fn values(self, f: &KeptFrame) -> &[f32] {
        match self {
            Self::Displacement => &f.elastic_abs,
            Self::VonMises => &f.von_mises,
        }
    }

    fn title(self) -> &'static str {
        match self {
            Self::Displacement => "Elastic displacement |u − u_rigid|",
            Self::VonMises => "Von Mises stress",
        }
    }

    /// The field and its unit, as the colour bars of the animations and the viewer name it.
    pub(crate) fn bar_title(self) -> &'static str {
        match self {
            Self::Displacement => "|u − u_rigid| [m]",
            Self::VonMises => "σ_vM [Pa]",
        }
    }
}

/// What every frame of an animation shares: magnification, viewport, optional wall.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Magnification of the elastic part.
    pub magnification: f64,
    /// `[xmin, ymin, xmax, ymax]` \[m\] containing every drawn position, the pivot and the wall.
    pub bounds: [f64; 4],
    /// Wall position \[m\], if any.
    pub wall_x: Option<f64>,
}

impl Scene {
    /// The scene of `frames`: magnification as given (or automatic) and the box around every
    /// drawn node over all frames, the pivot and the wall, padded by 4 %.
    pub fn new(nodes: &[[f64; 2]], frames: &[KeptFrame], magnification: Option<f64>, wall_x: Option<f64>) -> Self {
        let magnification = magnification.unwrap_or_else(|| auto_magnification(nodes, frames));
        let mut b = [0.0f64, 0.0, 0.0, 0.0];
        for f in frames {
            for p in f.drawn_positions(nodes, magnification) {
                b = [b[0].min(p[0]), b[1].min(p[1]), b[2].max(p[0]), b[3].max(p[1])];
            }
        }
        if frames.is_empty() {
            for p in nodes {
                b = [b[0].min(p[0]), b[1].min(p[1]), b[2].max(p[0]), b[3].max(p[1])];
            }
        }
        if let Some(w) = wall_x {
            // room for a band of wall left of the face: 6 % of the picture's size
            let size = (b[2] - b[0]).max(b[3] - b[1]).max(1e-9);
            b[0] = b[0].min(w - 0.06 * size);
            b[2] = b[2].max(w);
        }
        let pad = 0.04 * (b[2] - b[0]).max(b[3] - b[1]).max(1e-9);
        Self {
            magnification,
            bounds: [b[0] - pad, b[1] - pad, b[2] + pad, b[3] + pad],
            wall_x,
        }
    }
}

/// Largest value of a field over all frames (1 if all are zero, so a scale always exists).
pub fn field_max(frames: &[KeptFrame], field: AnimField) -> f64 {
    let m = frames
        .iter()
        .flat_map(|f| field.values(f).iter())
        .fold(0.0f32, |a, &v| a.max(v)) as f64;
    if m > 0.0 && m.is_finite() {
        m
    } else {
        1.0
    }
}

/// Frame size of the animations in pixels.
pub const GIF_SIZE: (usize, usize) = (640, 600);
const PLOT: [i32; 4] = [12, 64, 520, 590]; // x0, y0, x1, y1 of the pendulum area
const BAR: [i32; 4] = [540, 100, 558, 560];

/// Palette index of the wall band's fill (a light grey).
pub const WALL_FILL: u8 = LIGHT_GREY;
/// Palette index of the wall band's hatching and face (a mid grey).
pub const WALL_HATCH: u8 = GREY;

/// The pixel column of the wall's face in the animation frames of `scene` (`None` without a wall).
pub fn wall_pixel_x(scene: &Scene) -> Option<f32> {
    scene.wall_x.map(|w| pixel_map(scene)([w, 0.0])[0])
}

/// The rigid wall, the half-plane left of the face at pixel column `face`: a light grey band from
/// the left edge of the pendulum area to the face, hatched at 45°, with a 3 px face line.
fn draw_wall_band(c: &mut Canvas, face: f32) {
    let face = (face.round() as i32).clamp(PLOT[0], PLOT[2]);
    let (x0, y0, y1) = (PLOT[0] + 1, PLOT[1] + 1, PLOT[3]);
    if face <= x0 {
        return;
    }
    c.fill_rect(x0, y0, face, y1, WALL_FILL);
    // hatching: lines x − y = const every 10 px, clipped to the band
    let mut k = x0 - y1;
    while k < face - y0 {
        for y in y0..y1 {
            let x = k + y;
            if (x0..face).contains(&x) {
                c.put(x, y, WALL_HATCH);
            }
        }
        k += 10;
    }
    c.fill_rect(face - 1, y0, face + 2, y1, WALL_HATCH);
}

/// Maps model coordinates \[m\] to pixels of the pendulum area (equal aspect, centred, y up).
pub(super) fn pixel_map(scene: &Scene) -> impl Fn([f64; 2]) -> [f32; 2] + Sync {
    let [x0, y0, x1, y1] = scene.bounds;
    let (pw, ph) = ((PLOT[2] - PLOT[0]) as f64, (PLOT[3] - PLOT[1]) as f64);
    let scale = (pw / (x1 - x0)).min(ph / (y1 - y0));
    let cx = PLOT[0] as f64 + 0.5 * pw - scale * 0.5 * (x0 + x1);
    let cy = PLOT[1] as f64 + 0.5 * ph + scale * 0.5 * (y0 + y1);
    move |p: [f64; 2]| [(cx + scale * p[0]) as f32, (cy - scale * p[1]) as f32]
}

/// Everything that does not change between frames: background, titles, caption, colour bar.
pub(super) fn frame_template(font: &Text, field: AnimField, vmax: f64, scene: &Scene) -> Canvas {
    let (w, h) = GIF_SIZE;
    let mut c = Canvas::new(w, h, WHITE);
    c.text(font, 17.0, field.title(), PLOT[0] as f32, 8.0, Anchor::TopLeft);
    let caption = format!(
        "rigid motion true scale, elastic part × {}",
        raster::two_digits(scene.magnification)
    );
    c.text(font, 13.0, &caption, (w - 8) as f32, 11.0, Anchor::TopRight);
    if let Some(face) = wall_pixel_x(scene) {
        draw_wall_band(&mut c, face);
    }
    // frame around the pendulum area
    let [x0, y0, x1, y1] = PLOT.map(|v| v as f32);
    for (a, b) in [
        ([x0, y0], [x1, y0]),
        ([x1, y0], [x1, y1]),
        ([x1, y1], [x0, y1]),
        ([x0, y1], [x0, y0]),
    ] {
        c.line(a, b, LIGHT_GREY);
    }
    // colour bar, value increasing upwards
    let [bx0, by0, bx1, by1] = BAR;
    for y in by0..by1 {
        let t = (by1 - 1 - y) as f32 / (by1 - by0 - 1) as f32;
        c.fill_rect(bx0, y, bx1, y + 1, raster::map_index(t));
    }
    c.text(
        font,
        13.0,
        field.bar_title(),
        (bx0 + bx1) as f32 / 2.0,
        (by0 - 30) as f32,
        Anchor::TopCenter,
    );
    let (ticks, step) = raster::ticks(vmax);
    for v in ticks {
        let y = by1 as f32 - 1.0 - (v / vmax) as f32 * (by1 - by0 - 1) as f32;
        c.line([bx1 as f32, y], [bx1 as f32 + 4.0, y], BLACK);
        c.text(
            font,
            12.0,
            &raster::tick_label(v, step),
            bx1 as f32 + 7.0,
            y,
            Anchor::MidLeft,
        );
    }
    c.text(
        font,
        11.0,
        &format!("max {}", raster::two_digits(vmax)),
        (bx0 + bx1) as f32 / 2.0,
        (by1 + 8) as f32,
        Anchor::TopCenter,
    );
    c
}
