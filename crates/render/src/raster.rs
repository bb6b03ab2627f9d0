//! A small palette-indexed rasteriser for the animations: one byte per pixel, indices into the fixed
//! 256-colour [`PALETTE`], so GIF frames need no colour quantisation at all.
//!
//! Palette layout: indices `0..VIRIDIS_LEN` are a viridis-like colour map (the polynomial fit of
//! matplotlib's viridis), then [`GREY_LEN`] greys from black to white, then a few accent colours.
//! Triangles are filled with the scalar interpolated linearly over the triangle (Gouraud shading of
//! the colour-map position), text is anti-aliased into the greys.

use super::font::Text;

/// Number of colour-map entries.
pub(crate) const VIRIDIS_LEN: usize = 200;
/// First grey (black).
pub(crate) const GREY0: u8 = VIRIDIS_LEN as u8;
/// Number of greys.
pub(crate) const GREY_LEN: usize = 32;
/// White.
pub(crate) const WHITE: u8 = GREY0 + GREY_LEN as u8 - 1;
/// Black.
pub(crate) const BLACK: u8 = GREY0;
/// Mid grey (frames, wall).
pub(crate) const GREY: u8 = GREY0 + 14;
/// Light grey (grid, tick marks).
pub(crate) const LIGHT_GREY: u8 = GREY0 + 26;
/// Red (the pivot).
pub(crate) const RED: u8 = GREY0 + GREY_LEN as u8;

/// The viridis-like map at `t ∈ [0, 1]` as 8-bit RGB (polynomial fit by Matt Zucker, CC0).
pub(crate) fn viridis(t: f64) -> [u8; 3] {
    const C: [[f64; 3]; 7] = [
        [
            0.277_727_327_223_417_7,
            0.005_407_344_544_966_578,
            0.334_099_805_335_306_1,
        ],
        [0.105_093_043_108_577_4, 1.404_613_529_898_575, 1.384_590_162_594_685],
        [
            -0.330_861_828_725_556_3,
            0.214_847_559_468_213,
            0.095_095_163_028_236_59,
        ],
        [-4.634_230_498_983_486, -5.799_100_973_351_585, -19.332_440_956_279_87],
        [6.228_269_936_347_081, 14.179_933_366_805_09, 56.690_552_600_681_05],
        [4.776_384_997_670_288, -13.745_145_377_746_01, -65.353_032_633_372_34],
        [-5.435_455_855_934_631, 4.645_852_612_178_535, 26.312_435_249_583_2],
    ];
    let t = t.clamp(0.0, 1.0);
    let mut rgb = [0u8; 3];
    for (k, out) in rgb.iter_mut().enumerate() {
        let v = C.iter().rev().fold(0.0, |acc, c| acc * t + c[k]);
        *out = (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    }
    rgb
}

/// The fixed GIF palette, `[r, g, b]` per index, 256 entries.
pub(crate) fn palette() -> Vec<[u8; 3]> {
    let mut p = Vec::with_capacity(256);
    for i in 0..VIRIDIS_LEN {
        p.push(viridis(i as f64 / (VIRIDIS_LEN - 1) as f64));
    }
    for i in 0..GREY_LEN {
        let g = (i as f64 / (GREY_LEN - 1) as f64 * 255.0).round() as u8;
        p.push([g, g, g]);
    }
    p.push([214, 39, 40]);
    p.resize(256, [0, 0, 0]);
    p
}

/// Palette index of the colour-map position `t ∈ [0, 1]`.
#[inline]
pub(crate) fn map_index(t: f32) -> u8 {
    let i = (t * (VIRIDIS_LEN - 1) as f32 + 0.5) as i32;
    i.clamp(0, VIRIDIS_LEN as i32 - 1) as u8
}

/// How a text box is placed relative to its anchor point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Anchor {
    /// Anchor at the top-left corner.
    TopLeft,
    /// Anchor at the top-right corner.
    TopRight,
    /// Anchor at the middle of the left edge.
    MidLeft,
    /// Anchor at the top centre.
    TopCenter,
}

/// A palette-indexed image.
#[derive(Clone, Debug)]
pub(crate) struct Canvas {
    /// Width in pixels.
    pub w: usize,
    /// Height in pixels.
    pub h: usize,
    /// Row-major palette indices.
    pub px: Vec<u8>,
}

impl Canvas {
    /// A canvas filled with `index`.
    pub(crate) fn new(w: usize, h: usize, index: u8) -> Self {
        Self {
            w,
            h,
            px: vec![index; w * h],
        }
    }

    /// Fills the rectangle `[x0, x1) × [y0, y1)` (clipped).
    pub(crate) fn fill_rect(&mut self, x0: i32, y0: i32, x1: i32, y1: i32, index: u8) {
        let (x0, x1) = (x0.max(0) as usize, (x1.max(0) as usize).min(self.w));
        let (y0, y1) = (y0.max(0) as usize, (y1.max(0) as usize).min(self.h));
        if x0 >= x1 {
            return;
        }
        for y in y0..y1 {
            self.px[y * self.w + x0..y * self.w + x1].fill(index);
        }
    }

    /// Sets one pixel (clipped).
    #[inline]
    pub(crate) fn put(&mut self, x: i32, y: i32, index: u8) {
        if x >= 0 && y >= 0 && (x as usize) < self.w && (y as usize) < self.h {
            self.px[y as usize * self.w + x as usize] = index;
        }
    }

    /// A one-pixel line from `a` to `b` (DDA).
    pub(crate) fn line(&mut self, a: [f32; 2], b: [f32; 2], index: u8) {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let n = dx.abs().max(dy.abs()).ceil().max(1.0) as i32;
        for i in 0..=n {
            let s = i as f32 / n as f32;
            self.put((a[0] + s * dx).floor() as i32, (a[1] + s * dy).floor() as i32, index);
        }
    }

    /// A filled disc of radius `r` around `c`.
    pub(crate) fn disc(&mut self, c: [f32; 2], r: f32, index: u8) {
        let (x0, x1) = ((c[0] - r).floor() as i32, (c[0] + r).ceil() as i32);
        let (y0, y1) = ((c[1] - r).floor() as i32, (c[1] + r).ceil() as i32);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (ex, ey) = (x as f32 + 0.5 - c[0], y as f32 + 0.5 - c[1]);
                if ex * ex + ey * ey <= r * r {
                    self.put(x, y, index);
                }
            }
        }
    }

    /// Fills the triangle `p` (pixel coordinates, either orientation) with colour-map positions
    /// `t` at its corners interpolated linearly in between.
    pub(crate) fn gouraud_triangle(&mut self, p: [[f32; 2]; 3], t: [f32; 3]) {
        let area = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
        if area == 0.0 || !area.is_finite() {
            return;
        }
        let inv = 1.0 / area;
        let xmin = p.iter().map(|q| q[0]).fold(f32::INFINITY, f32::min).floor().max(0.0) as usize;
        let xmax = (p.iter().map(|q| q[0]).fold(f32::NEG_INFINITY, f32::max).ceil() as i64).min(self.w as i64 - 1);
        let ymin = p.iter().map(|q| q[1]).fold(f32::INFINITY, f32::min).floor().max(0.0) as usize;
        let ymax = (p.iter().map(|q| q[1]).fold(f32::NEG_INFINITY, f32::max).ceil() as i64).min(self.h as i64 - 1);
        if xmax < 0 || ymax < 0 {
            return;
        }
        // Barycentric weights b_i = e_i(x, y) / area, each affine in x: b_i = a_i x + c_i(y).
        let edge = |i: usize| {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            // e_i(q) = (p_k − p_j) × (q − p_j)
            let ax = -(p[k][1] - p[j][1]) * inv;
            let ay = (p[k][0] - p[j][0]) * inv;
            let c = -(ax * p[j][0] + ay * p[j][1]);
            (ax, ay, c)
        };
        let e = [edge(0), edge(1), edge(2)];
        const EPS: f32 = -1e-4;
        for y in ymin..=ymax as usize {
            let yc = y as f32 + 0.5;
            let row = y * self.w;
            for x in xmin..=xmax as usize {
                let xc = x as f32 + 0.5;
                let b0 = e[0].0 * xc + e[0].1 * yc + e[0].2;
                let b1 = e[1].0 * xc + e[1].1 * yc + e[1].2;
                let b2 = 1.0 - b0 - b1;
                if b0 >= EPS && b1 >= EPS && b2 >= EPS {
                    self.px[row + x] = map_index(b0 * t[0] + b1 * t[1] + b2 * t[2]);
                }
            }
        }
    }

    /// Draws anti-aliased black text (blended into the greys; any non-grey background counts as white).
    pub(crate) fn text(&mut self, font: &Text, size: f32, s: &str, x: f32, y: f32, anchor: Anchor) {
        let width = font.width(size, s);
        let (x0, y0) = match anchor {
            Anchor::TopLeft => (x, y),
            Anchor::TopRight => (x - width, y),
            Anchor::MidLeft => (x, y - 0.6 * size),
            Anchor::TopCenter => (x - 0.5 * width, y),
        };
        let (w, h) = (self.w as i32, self.h as i32);
        font.draw(size, s, x0.round(), y0.round(), |px, py, c| {
            if px < 0 || py < 0 || px >= w || py >= h {
                return;
            }
            let i = py as usize * self.w + px as usize;
            let bg = self.px[i];
            let level = if (GREY0..=WHITE).contains(&bg) {
                (bg - GREY0) as f32
            } else {
                (GREY_LEN - 1) as f32
            };
            self.px[i] = GREY0 + (level * (1.0 - c)).round() as u8;
        });
    }
}

/// "Nice" tick values from 0 to `max` (about five), all `<= max`.
pub(crate) fn ticks(max: f64) -> (Vec<f64>, f64) {
    if !(max > 0.0 && max.is_finite()) {
        return (vec![0.0], 1.0);
    }
    let raw = max / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let n = (max / step * (1.0 + 1e-9)).floor() as usize;
    ((0..=n).map(|i| i as f64 * step).collect(), step)
}

/// A tick label: plain decimals for moderate magnitudes, else `1.5e5` notation.
pub(crate) fn tick_label(v: f64, step: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if (1e-3..1e4).contains(&step) {
        let decimals = (-(step.log10().floor()) as i32
            + if (step / 10f64.powf(step.log10().floor())).fract() > 1e-9 {
                1
            } else {
                0
            })
        .max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        // the fewest mantissa decimals that print the tick exactly: 2.5e4 (not "2e4"), 5e4, 1e5
        (0..=4)
            .map(|d| format!("{v:.d$e}"))
            .find(|text| text.parse::<f64>().is_ok_and(|x| (x - v).abs() <= 1e-9 * step))
            .unwrap_or_else(|| format!("{v:e}"))
    }
}

/// `x` with two significant digits, in `1.2e5` notation (plain for 0.1 ≤ x < 1000).
pub(crate) fn two_digits(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    if (0.1..1000.0).contains(&x.abs()) {
        let d = (1 - x.abs().log10().floor() as i32).max(0) as usize;
        format!("{x:.d$}")
    } else {
        format!("{x:.1e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_nice_and_within_range() {
        let (t, s) = ticks(0.0734);
        assert_eq!(s, 0.02);
        assert_eq!(t.len(), 4);
        let (t, s) = ticks(3.1e6);
        assert_eq!(s, 1e6);
        assert_eq!(t.last().copied(), Some(3e6));
    }

    #[test]
    fn tick_labels_read_well_and_print_every_tick_exactly() {
        assert_eq!(tick_label(0.04, 0.02), "0.04");
        assert_eq!(tick_label(0.025, 0.025), "0.025");
        assert_eq!(tick_label(2e6, 1e6), "2e6");
        assert_eq!(tick_label(2.5e6, 5e5), "2.5e6");
        assert_eq!(tick_label(2e-5, 1e-5), "2e-5");
        // the von Mises colour bar of the default run: ticks every 2.5e4 Pa
        let labels: Vec<String> = [0.0, 2.5e4, 5e4, 7.5e4, 1e5]
            .iter()
            .map(|&v| tick_label(v, 2.5e4))
            .collect();
        assert_eq!(labels, ["0", "2.5e4", "5e4", "7.5e4", "1e5"]);
        assert_eq!(tick_label(1.5e-6, 2.5e-7), "1.5e-6");
        assert_eq!(two_digits(123456.0), "1.2e5");
        assert_eq!(two_digits(12.0), "12");
        assert_eq!(two_digits(0.5), "0.50");
    }

    #[test]
    fn palette_has_256_entries_and_viridis_ends() {
        let p = palette();
        assert_eq!(p.len(), 256);
        assert_eq!(p[WHITE as usize], [255, 255, 255]);
        assert_eq!(p[BLACK as usize], [0, 0, 0]);
        assert!(p[0][2] > p[0][1], "viridis starts dark purple");
        assert!(p[VIRIDIS_LEN - 1][1] > 200, "viridis ends yellow");
    }
}
