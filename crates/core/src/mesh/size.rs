//! The graded mesh-size field.
//!
//! ```text
//! h(x) = min( h_max,  min over sources s of ( h_s + g · dist(x, s) ) )
//! ```
//!
//! Sources are the sized boundary edges (exact lines and arcs), the sized corners and the sized
//! regions (distance 0 inside, so a region's size applies everywhere in it). `g` is the grading
//! (Netgen's `grading`, default 0.3): `h` is Lipschitz with constant `g`, so neighbouring
//! elements differ in size by at most a factor of about `1 + g`.

use crate::geometry::{Curve, Point, Shape, Solid};

/// A size field built from a [`Shape`]'s size sources.
#[derive(Clone, Debug)]
pub struct SizeField {
    max_size: f64,
    grading: f64,
    edges: Vec<(Curve, f64)>,
    corners: Vec<(Point, f64)>,
    regions: Vec<(Solid, f64)>,
}

impl SizeField {
    /// The field of `shape` capped at `max_size`, growing with slope `grading`.
    pub fn new(shape: &Shape, max_size: f64, grading: f64) -> Self {
        Self {
            max_size,
            grading,
            edges: shape
                .edges
                .iter()
                .filter_map(|e| e.size.map(|s| (e.curve, s)))
                .collect(),
            corners: shape.corners.iter().map(|c| (c.point, c.size)).collect(),
            regions: shape.regions.iter().map(|r| (r.solid.clone(), r.size)).collect(),
        }
    }

    /// `h(x)` \[m\].
    pub fn at(&self, p: Point) -> f64 {
        let g = self.grading;
        let mut h = self.max_size;
        for (solid, s) in &self.regions {
            if *s < h {
                h = h.min(s + g * solid.distance(p));
            }
        }
        for (curve, s) in &self.edges {
            if *s < h {
                h = h.min(s + g * curve.distance(p));
            }
        }
        for (q, s) in &self.corners {
            if *s < h {
                h = h.min(s + g * ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt());
            }
        }
        h
    }
}
