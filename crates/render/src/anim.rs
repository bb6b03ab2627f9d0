//! Animated GIFs of the swinging pendulum: `displacement.gif` (coloured by the magnitude of the
//! elastic displacement, the part it magnifies, \[m\]) and `von_mises.gif` (coloured by the von
//! Mises stress \[Pa\]).
//!
//! ## What is drawn
//!
//! A steel pendulum deforms by micrometres, invisible at true scale, so the picture splits the
//! displacement `u` of a node at reference position `X` into the rigid rotation by the frame's
//! proxy angle `θ` and the rest:
//!
//! ```text
//! elastic = u − (R(θ) X − X),        drawn position = R(θ) X + m · elastic,
//! ```
//!
//! i.e. the swing is at true scale and only the elastic part is magnified by `m`. `m` is
//! `output.magnification` or, when that is unset, chosen so that the largest elastic displacement
//! over the kept frames is drawn as 5 % of the pendulum size (largest `|X|`), rounded to two
//! significant digits; every frame states it ("elastic part × 1.2e5"). The colour scale runs from
//! 0 to the largest value over all kept frames, so colours compare across frames; a colour bar
//! with ticks in physical units, the time, the pivot (a red dot at the origin) and, optionally, the
//! rigid wall (the half-plane `x ≤ wall_x`: a hatched light grey band from the left edge of the
//! picture to a grey face line at `x = wall_x`, with room for it kept left of the face) are drawn on
//! every frame.
//!
//! Each six-node triangle is drawn as four straight sub-triangles through its corner and mid-edge
//! nodes, the colour interpolated linearly over each (`raster.rs`).
//!
//! ## Memory and speed
//!
//! [`KeptFrames`] holds at most `output.max_frames` frames whatever the run length: when full, it
//! drops every second frame and doubles its stride. A kept frame stores the elastic displacement,
//! |u|, the elastic |u| and von Mises per node in `f32` (enough for pictures), about 20 bytes per node.
//!
//! GIF frames index a fixed 256-colour palette directly (200 colour-map entries, greys, a red):
//! no colour quantisation. Frames are rasterised and LZW-compressed in parallel (rayon), a chunk
//! at a time, and written in order; every frame after the first stores only the rectangle that
//! changed since the frame before (disposal "keep"), which more than halves the compression work
//! (the time label sits above the pivot for that reason). Playback: the frame delay is the simulated time between kept frames, at least
//! 20 ms (what browsers honour) and at most 0.5 s.

use std::path::Path;

use rayon::prelude::*;

use super::font::Text;
use super::raster::{self, Anchor, Canvas, BLACK, GREY, LIGHT_GREY, RED, WHITE};
use super::Frame;
use crate::{Error, Mesh};

/// The part of one frame kept for the animations and the viewer.
#[derive(Clone, Debug, PartialEq)]
pub struct KeptFrame {
    /// Step number.
    pub step: usize,
    /// Time \[s\].
    pub time: f64,
    /// Proxy angle \[rad\].
    pub theta: f64,
    /// Elastic displacement `u − (R(θ)X − X)` per node \[m\].
    pub elastic: Vec<[f32; 2]>,
    /// |u| per node \[m\] (the viewer's displacement field).
    pub u_abs: Vec<f32>,
    /// |elastic| per node \[m\]: what `displacement.gif` colours. The total |u| is nearly all rigid
    /// rotation (0–0.10 m for the tutorial's swing), while the shape drawn magnifies the elastic
    /// part by about 2e5: colouring |u| showed the swing's angle, not the deformation drawn.
    pub elastic_abs: Vec<f32>,
    /// Von Mises stress per node \[Pa\].
    pub von_mises: Vec<f32>,
    /// The nodes `0..rotating` (the pendulum's) turn with θ; the nodes after them (a second
    /// body, such as a deformable wall) do not: their `elastic` is their whole displacement and
    /// they are drawn at `X + m · u`.
    pub rotating: usize,
}

impl KeptFrame {
    /// Extracts what the pictures need from a frame of the mesh `nodes`.
    pub fn from_frame(nodes: &[[f64; 2]], frame: &Frame<'_>) -> Self {
        Self::from_frame_of_bodies(nodes, nodes.len(), frame)
    }

    /// [`KeptFrame::from_frame`] for a model of several bodies: only the nodes `0..rotating` (the
    /// pendulum's) turn with θ (see [`KeptFrame::rotating`]).
    pub fn from_frame_of_bodies(nodes: &[[f64; 2]], rotating: usize, frame: &Frame<'_>) -> Self {
        let (s, c) = frame.theta.sin_cos();
        let elastic: Vec<[f32; 2]> = nodes
            .iter()
            .zip(frame.displacement)
            .enumerate()
            .map(|(i, (x, u))| {
                if i >= rotating {
                    return [u[0] as f32, u[1] as f32];
                }
                let rigid = [c * x[0] - s * x[1] - x[0], s * x[0] + c * x[1] - x[1]];
                [(u[0] - rigid[0]) as f32, (u[1] - rigid[1]) as f32]
            })
            .collect();
        Self {
            step: frame.step,
            time: frame.time,
            theta: frame.theta,
            elastic_abs: elastic.iter().map(|e| e[0].hypot(e[1])).collect(),
            elastic,
            u_abs: frame.displacement.iter().map(|u| u[0].hypot(u[1]) as f32).collect(),
            von_mises: frame.von_mises.iter().map(|&v| v as f32).collect(),
            rotating,
        }
    }

    /// Drawn positions `R(θ)X + m · elastic` \[m\].
    pub fn drawn_positions(&self, nodes: &[[f64; 2]], magnification: f64) -> Vec<[f64; 2]> {
        let (s, c) = self.theta.sin_cos();
        nodes
            .iter()
            .zip(&self.elastic)
            .enumerate()
            .map(|(i, (x, e))| {
                let at = if i < self.rotating {
                    [c * x[0] - s * x[1], s * x[0] + c * x[1]]
                } else {
                    *x
                };
                [at[0] + magnification * e[0] as f64, at[1] + magnification * e[1] as f64]
            })
            .collect()
    }
}

/// A bounded, evenly thinned collection of frames (at most `max_frames`).
///
/// Offered frames are numbered `0, 1, 2, …` in arrival order; frame `k` is kept when `k` is a
/// multiple of the stride. When a kept frame would exceed `max_frames`, every second kept frame is
/// dropped and the stride doubles. The most recent offered frame is held aside so that
/// [`KeptFrames::into_frames`] can end on the last state of the run.
#[derive(Clone, Debug)]
pub struct KeptFrames {
    max_frames: usize,
    stride: usize,
    offered: usize,
    frames: Vec<KeptFrame>,
    last: Option<KeptFrame>,
}

impl KeptFrames {
    /// An empty collection keeping at most `max_frames` (at least 2) frames.
    pub fn new(max_frames: usize) -> Self {
        Self {
            max_frames: max_frames.max(2),
            stride: 1,
            offered: 0,
            frames: Vec::new(),
            last: None,
        }
    }

    /// Offers the next frame.
    pub fn push(&mut self, frame: KeptFrame) {
        let k = self.offered;
        self.offered += 1;
        if !k.is_multiple_of(self.stride) {
            self.last = Some(frame);
            return;
        }
        self.last = None;
        if self.frames.len() == self.max_frames {
            // Keep indices that are multiples of 2·stride: the even positions of the kept list.
            let mut i = 0;
            self.frames.retain(|_| {
                i += 1;
                (i - 1) % 2 == 0
            });
            self.stride *= 2;
            if !k.is_multiple_of(self.stride) {
                self.last = Some(frame);
                return;
            }
        }
        self.frames.push(frame);
    }

    /// Number of frames currently kept (not counting the held-aside last one).
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// Whether nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty() && self.last.is_none()
    }

    /// Current stride between kept frames (in offered frames).
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// The kept frames in time order, ending with the last offered one (at most `max_frames`).
    pub fn into_frames(mut self) -> Vec<KeptFrame> {
        if let Some(last) = self.last.take() {
            if self.frames.len() == self.max_frames {
                self.frames.pop();
            }
            self.frames.push(last);
        }
        self.frames
    }
}

/// The automatic magnification: the largest elastic displacement over `frames` is drawn as 5 % of
/// the pendulum size (largest `|X|`), rounded to two significant digits; 1 when nothing deforms.
pub fn auto_magnification(nodes: &[[f64; 2]], frames: &[KeptFrame]) -> f64 {
    let size = nodes.iter().map(|x| x[0].hypot(x[1])).fold(0.0, f64::max);
    let e_max = frames
        .iter()
        .flat_map(|f| f.elastic.iter())
        .map(|e| (e[0] as f64).hypot(e[1] as f64))
        .fold(0.0, f64::max);
    if size.is_nan() || size <= 0.0 || e_max.is_nan() || e_max <= size * 1e-12 {
        return 1.0;
    }
    let m = 0.05 * size / e_max;
    let mag = 10f64.powf(m.log10().floor() - 1.0);
    ((m / mag).round() * mag).max(f64::MIN_POSITIVE)
}

/// Which field an animation shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnimField {
    /// The magnitude of the elastic displacement \[m\] ([`KeptFrame::elastic_abs`]).
    Displacement,
    /// Von Mises stress \[Pa\].
    VonMises,
}

impl AnimField {
    fn values(self, f: &KeptFrame) -> &[f32] {
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

    fn bar_title(self) -> &'static str {
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

/// Writes one animated GIF of `frames` (time order) coloured by `field`.
pub fn write_gif(path: &Path, mesh: &Mesh, frames: &[KeptFrame], field: AnimField, scene: &Scene) -> Result<(), Error> {
    let (w, h) = GIF_SIZE;
    let font = Text::new();
    let vmax = field_max(frames, field);
    let template = frame_template(&font, field, vmax, scene);
    let to_px = pixel_map(scene);
    // Sub-triangles (local node indices of the Tri6): corners with their adjacent mid-edge nodes, and the middle one.
    const SUB: [[usize; 3]; 4] = [[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]];

    let render = |i: usize| -> Canvas {
        let f = &frames[i];
        let mut c = template.clone();
        let pos: Vec<[f32; 2]> = f
            .drawn_positions(&mesh.nodes, scene.magnification)
            .into_iter()
            .map(&to_px)
            .collect();
        let vals = field.values(f);
        let inv = 1.0 / vmax as f32;
        for tri in &mesh.triangles {
            for s in SUB {
                let n = [tri[s[0]], tri[s[1]], tri[s[2]]];
                c.gouraud_triangle(
                    [pos[n[0]], pos[n[1]], pos[n[2]]],
                    [vals[n[0]] * inv, vals[n[1]] * inv, vals[n[2]] * inv],
                );
            }
        }
        for e in &mesh.boundary_edges {
            c.line(pos[e.nodes[0]], pos[e.nodes[2]], BLACK);
            c.line(pos[e.nodes[2]], pos[e.nodes[1]], BLACK);
        }
        let pivot = to_px([0.0, 0.0]);
        c.disc(pivot, 5.0, BLACK);
        c.disc(pivot, 3.5, RED);
        // Above the pivot, so that the region changing between frames stays narrow.
        c.text(
            &font,
            16.0,
            // the rigid rotation, drawn at true scale, stated beside the time
            &format!("t = {:.3} s, θ = {:.1}°", f.time, f.theta.to_degrees()),
            pivot[0],
            38.0,
            Anchor::TopCenter,
        );
        c
    };

    let palette: Vec<u8> = raster::palette().into_iter().flatten().collect();
    crate::write_atomically(path, |out| {
        let mut enc = gif::Encoder::new(out, w as u16, h as u16, &palette).map_err(std::io::Error::other)?;
        enc.set_repeat(gif::Repeat::Infinite).map_err(std::io::Error::other)?;
        // Render and compress in parallel, a chunk of frames at a time (bounded memory); each frame
        // after the first stores only the rectangle that differs from the frame before.
        let mut previous: Option<Canvas> = None;
        let indices: Vec<usize> = (0..frames.len()).collect();
        for chunk in indices.chunks(4 * rayon::current_num_threads().max(1)) {
            let canvases: Vec<Canvas> = chunk.par_iter().map(|&i| render(i)).collect();
            let encoded: Vec<gif::Frame<'static>> = (0..chunk.len())
                .into_par_iter()
                .map(|k| {
                    let before = if k == 0 {
                        previous.as_ref()
                    } else {
                        Some(&canvases[k - 1])
                    };
                    let mut frame = changed_rect_frame(&canvases[k], before);
                    frame.delay = delay_cs(frames, chunk[k]);
                    frame.make_lzw_pre_encoded();
                    frame
                })
                .collect();
            for f in &encoded {
                enc.write_lzw_pre_encoded_frame(f).map_err(std::io::Error::other)?;
            }
            previous = canvases.into_iter().last();
        }
        enc.into_inner().map_err(std::io::Error::other)?;
        Ok(())
    })
}

/// A GIF frame holding the smallest rectangle of `c` that differs from `before` (all of `c` when
/// there is no frame before), drawn over the previous frame (disposal "keep").
fn changed_rect_frame(c: &Canvas, before: Option<&Canvas>) -> gif::Frame<'static> {
    let (w, h) = (c.w, c.h);
    let (mut x0, mut y0, mut x1, mut y1) = (0, 0, w, h);
    if let Some(b) = before {
        let (mut bx0, mut by0, mut bx1, mut by1) = (w, h, 0, 0);
        for y in 0..h {
            let (r, s) = (&c.px[y * w..(y + 1) * w], &b.px[y * w..(y + 1) * w]);
            if r == s {
                continue;
            }
            let first = r.iter().zip(s).position(|(p, q)| p != q).unwrap_or(0);
            let last = w - r
                .iter()
                .rev()
                .zip(s.iter().rev())
                .position(|(p, q)| p != q)
                .unwrap_or(0);
            (bx0, bx1, by0, by1) = (bx0.min(first), bx1.max(last), by0.min(y), y + 1);
        }
        (x0, y0, x1, y1) = if bx1 > bx0 { (bx0, by0, bx1, by1) } else { (0, 0, 1, 1) };
    }
    let mut px = Vec::with_capacity((x1 - x0) * (y1 - y0));
    for y in y0..y1 {
        px.extend_from_slice(&c.px[y * w + x0..y * w + x1]);
    }
    let mut frame = gif::Frame::from_indexed_pixels((x1 - x0) as u16, (y1 - y0) as u16, px, None);
    frame.left = x0 as u16;
    frame.top = y0 as u16;
    frame.dispose = gif::DisposalMethod::Keep;
    frame
}

/// Frame delay in hundredths of a second: the simulated time to the next frame, 2 to 50.
fn delay_cs(frames: &[KeptFrame], i: usize) -> u16 {
    let dt = if i + 1 < frames.len() {
        frames[i + 1].time - frames[i].time
    } else if i > 0 {
        frames[i].time - frames[i - 1].time
    } else {
        0.0
    };
    (dt * 100.0).round().clamp(2.0, 50.0) as u16
}

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
fn pixel_map(scene: &Scene) -> impl Fn([f64; 2]) -> [f32; 2] + Sync {
    let [x0, y0, x1, y1] = scene.bounds;
    let (pw, ph) = ((PLOT[2] - PLOT[0]) as f64, (PLOT[3] - PLOT[1]) as f64);
    let scale = (pw / (x1 - x0)).min(ph / (y1 - y0));
    let cx = PLOT[0] as f64 + 0.5 * pw - scale * 0.5 * (x0 + x1);
    let cy = PLOT[1] as f64 + 0.5 * ph + scale * 0.5 * (y0 + y1);
    move |p: [f64; 2]| [(cx + scale * p[0]) as f32, (cy - scale * p[1]) as f32]
}

/// Everything that does not change between frames: background, titles, caption, colour bar.
fn frame_template(font: &Text, field: AnimField, vmax: f64, scene: &Scene) -> Canvas {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn dummy(step: usize) -> KeptFrame {
        KeptFrame {
            step,
            time: step as f64,
            theta: 0.0,
            elastic: vec![],
            u_abs: vec![],
            elastic_abs: vec![],
            von_mises: vec![],
            rotating: 0,
        }
    }

    /// `keep` applied to a frame of two nodes displaced by `u` at angle `theta` (no velocity,
    /// acceleration or stress).
    fn two_node_frame(theta: f64, u: &[[f64; 2]; 2], keep: impl Fn(&Frame<'_>) -> KeptFrame) -> KeptFrame {
        let zeros = [[0.0; 2]; 2];
        keep(&Frame {
            step: 1,
            time: 0.01,
            theta,
            displacement: u,
            velocity: &zeros,
            acceleration: &zeros,
            von_mises: &[0.0; 2],
            cauchy: &[[0.0; 3]; 2],
        })
    }

    #[test]
    fn the_displacement_animation_colours_the_elastic_part_it_magnifies_not_the_rigid_swing() {
        // node 0 turned rigidly by θ (|u| = 0.06 m, no elastic part); node 1 the same plus 1 µm
        let nodes = [[0.0, -0.3], [0.01, -0.3]];
        let theta: f64 = 0.2;
        let (s, c) = theta.sin_cos();
        let rigid = |x: [f64; 2]| [c * x[0] - s * x[1] - x[0], s * x[0] + c * x[1] - x[1]];
        let (r0, r1) = (rigid(nodes[0]), rigid(nodes[1]));
        let u = [r0, [r1[0] + 1e-6, r1[1]]];
        let f = two_node_frame(theta, &u, |frame| KeptFrame::from_frame(&nodes, frame));
        let shown = AnimField::Displacement.values(&f);
        // f32 storage: the rigid part of 0.06 m cancels to within its rounding, ~1e-8 m
        assert!(shown[0] < 1e-8, "rigid node coloured {}", shown[0]);
        assert!((shown[1] - 1e-6).abs() < 2e-8, "elastic node coloured {}", shown[1]);
        assert!(f.u_abs[0] > 0.05, "the viewer's |u| stays the total: {}", f.u_abs[0]);
    }

    #[test]
    fn nodes_of_a_second_body_do_not_turn_with_the_pendulum() {
        // node 0 is the pendulum's, node 1 a wall's; both displaced by the same u
        let nodes = [[0.0, -0.3], [-0.1, -0.3]];
        let theta: f64 = 0.2;
        let u = [[0.3 * theta.sin(), 0.3 - 0.3 * theta.cos()], [1e-6, 0.0]];
        let f = two_node_frame(theta, &u, |frame| KeptFrame::from_frame_of_bodies(&nodes, 1, frame));
        assert!(
            f.elastic[0][0].abs() < 1e-7 && f.elastic[0][1].abs() < 1e-7,
            "{:?}",
            f.elastic[0]
        );
        assert_eq!(f.elastic[1], [1e-6, 0.0]);
        let p = f.drawn_positions(&nodes, 1e4);
        assert!(
            (p[0][0] - u[0][0]).abs() < 1e-6 && (p[0][1] - (-0.3 + u[0][1])).abs() < 1e-6,
            "{:?}",
            p[0]
        );
        assert!((p[1][0] - (-0.1 + 1e-2)).abs() < 1e-9 && p[1][1] == -0.3, "{:?}", p[1]);
        // one body: every node turns, as before
        assert_eq!(
            two_node_frame(theta, &u, |frame| KeptFrame::from_frame(&nodes, frame)).rotating,
            2
        );
    }

    #[test]
    fn kept_frames_stay_bounded_and_evenly_spaced() {
        let mut k = KeptFrames::new(10);
        for s in 0..1000 {
            k.push(dummy(s));
            assert!(k.len() <= 10);
        }
        let frames = k.into_frames();
        assert!(frames.len() <= 10 && frames.len() >= 5, "{}", frames.len());
        assert_eq!(frames[0].step, 0);
        assert_eq!(frames.last().unwrap().step, 999, "ends on the last state");
        let d = frames[1].step - frames[0].step;
        for w in frames[..frames.len() - 1].windows(2) {
            assert_eq!(w[1].step - w[0].step, d);
        }
    }

    #[test]
    fn thinning_holds_for_every_bound_and_run_length() {
        for max in 2..20 {
            for n in 1..300 {
                let mut k = KeptFrames::new(max);
                for s in 0..n {
                    k.push(dummy(s));
                }
                let frames = k.into_frames();
                assert!(frames.len() <= max, "max {max}, n {n}: {}", frames.len());
                assert!(
                    frames.len() >= max.min(n) / 2,
                    "max {max}, n {n}: only {}",
                    frames.len()
                );
                assert_eq!(frames[0].step, 0);
                assert_eq!(frames.last().unwrap().step, n - 1);
                assert!(frames.windows(2).all(|w| w[1].step > w[0].step));
            }
        }
    }

    #[test]
    fn few_frames_are_all_kept() {
        let mut k = KeptFrames::new(10);
        for s in 0..7 {
            k.push(dummy(s));
        }
        let steps: Vec<usize> = k.into_frames().iter().map(|f| f.step).collect();
        assert_eq!(steps, (0..7).collect::<Vec<_>>());
    }

    #[test]
    fn auto_magnification_makes_elastic_five_percent_of_size() {
        let nodes = [[0.0, 0.0], [0.0, -0.3]];
        let mut f = dummy(0);
        f.elastic = vec![[0.0, 0.0], [1e-6, 0.0]];
        let m = auto_magnification(&nodes, &[f]);
        assert!((m * 1e-6 - 0.015).abs() < 0.015 * 0.05, "{m}");
    }
}
