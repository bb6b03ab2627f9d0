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
//! its magnitude and von Mises per node in `f32` (enough for pictures), 16 bytes per node.
//!
//! GIF frames index a fixed 256-colour palette directly (200 colour-map entries, greys, a red):
//! no colour quantisation. Frames are rasterised and LZW-compressed in parallel (rayon), a chunk
//! at a time, and written in order; every frame after the first stores only the rectangle that
//! changed since the frame before (disposal "keep"), so the unchanged rest of the picture is not
//! compressed again (the time label sits above the pivot for that reason). Playback: the frame
//! delay is the simulated time between kept frames, at least 20 ms (what browsers honour) and at
//! most 0.5 s.

mod encode;
mod kept;
mod scene;

pub use encode::write_gif;
pub use kept::{auto_magnification, KeptFrame, KeptFrames};
pub use scene::{field_max, wall_pixel_x, AnimField, Scene, GIF_SIZE, WALL_FILL, WALL_HATCH};
