//! The one font every picture uses: DejaVu Sans, shipped in `crates/render/assets/fonts/` (licence beside it)
//! and compiled into the binary, so no system font is ever looked up.
//!
//! Plots ([`super::plot`]) draw text through plotters' `ab_glyph` backend, which knows only fonts
//! registered by name: [`register_for_plotters`] registers the font as `sans-serif` (once per
//! process). Animations ([`super::anim`]) rasterise text themselves with [`Text`], straight into
//! palette-indexed pixels.

use ab_glyph::{point, Font, FontRef, PxScale, ScaleFont};
use std::sync::Once;

/// The TrueType file of DejaVu Sans (Bitstream Vera licence, see `crates/render/assets/fonts/DejaVuSans-LICENSE.txt`).
pub(crate) const FONT_BYTES: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

/// Registers the shipped font with plotters as the `sans-serif` family (idempotent).
pub(crate) fn register_for_plotters() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        plotters::style::register_font("sans-serif", plotters::style::FontStyle::Normal, FONT_BYTES).unwrap_or_else(
            |_| panic!("the shipped font crates/render/assets/fonts/DejaVuSans.ttf is not a valid TrueType file"),
        );
    });
}

/// A text rasteriser over the shipped font.
pub(crate) struct Text {
    font: FontRef<'static>,
}

impl Text {
    /// Parses the shipped font.
    pub(crate) fn new() -> Self {
        let font = FontRef::try_from_slice(FONT_BYTES).expect("the shipped font is a valid TrueType file");
        Self { font }
    }

    /// Advance width of `s` at pixel size `px`.
    pub(crate) fn width(&self, px: f32, s: &str) -> f32 {
        let scaled = self.font.as_scaled(PxScale::from(px));
        let mut caret = 0.0;
        let mut prev = None;
        for c in s.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = prev {
                caret += scaled.kern(p, id);
            }
            caret += scaled.h_advance(id);
            prev = Some(id);
        }
        caret
    }

    /// Rasterises `s` with its box's top-left corner at `(x, y_top)`: calls `put(x, y, coverage)`
    /// for every touched pixel, coverage in `(0, 1]`.
    pub(crate) fn draw(&self, px: f32, s: &str, x: f32, y_top: f32, mut put: impl FnMut(i32, i32, f32)) {
        let scaled = self.font.as_scaled(PxScale::from(px));
        let baseline = y_top + scaled.ascent();
        let mut caret = x;
        let mut prev = None;
        for c in s.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = prev {
                caret += scaled.kern(p, id);
            }
            let glyph = id.with_scale_and_position(px, point(caret, baseline));
            caret += scaled.h_advance(id);
            prev = Some(id);
            if let Some(outline) = self.font.outline_glyph(glyph) {
                let b = outline.px_bounds();
                outline.draw(|gx, gy, c| {
                    if c > 0.0 {
                        put(b.min.x as i32 + gx as i32, b.min.y as i32 + gy as i32, c.min(1.0));
                    }
                });
            }
        }
    }
}
