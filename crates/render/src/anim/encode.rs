//! The GIF encoding of an animation: each kept frame drawn over the template, frames rasterised and
//! LZW-compressed in parallel a chunk at a time, only the changed rectangle stored, with the delay
//! of the simulated time between frames.

use std::path::Path;

use rayon::prelude::*;

use super::kept::KeptFrame;
use super::scene::{field_max, frame_template, pixel_map, AnimField, Scene, GIF_SIZE};
use crate::font::Text;
use crate::raster::{self, Anchor, Canvas, BLACK, RED};
use crate::{Error, Mesh};

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
    pendulum_fem_core::store::write_atomically(path, |out| {
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
