//! Constructive solid geometry of straight and circular edges, with names and local mesh sizes.
//!
//! A [`Shape`] is a closed region described twice, exactly:
//!
//! * by its boundary, a list of [`Edge`]s, each a line segment or a circular arc ([`Curve`]),
//!   oriented with the region on the left, carrying a boundary name and optionally a local mesh
//!   size;
//! * by a point-membership tree ([`Solid`]): convex polygons and discs combined by union and
//!   difference.
//!
//! The booleans work on the boundary: every edge of one operand is cut at its intersections with
//! the edges of the other (line–line, line–circle and circle–circle intersections are solved in
//! closed form, so the cut points lie exactly on both curves up to rounding), and each piece is
//! kept or dropped by testing its parametric midpoint against the other operand's [`Solid`]:
//!
//! ```text
//! A ∪ B :  pieces of ∂A outside B  +  pieces of ∂B outside A
//! A − B :  pieces of ∂A outside B  +  pieces of ∂B inside A, reversed
//! ```
//!
//! Pieces keep the name and size of the edge they come from, so names survive the booleans.
//! Overlapping (collinear or concentric-equal) boundary pieces are not supported; they do not
//! occur for the rectangle/disc combinations of the pendulum. Rotation about a point is exact
//! (it maps lines to lines and arcs to arcs).
//!
//! Sizes: every edge may carry a size (the mesh size along it), [`Shape::corners`] are point
//! sources, and [`Shape::regions`] give a size inside a primitive solid (the rod rectangle, the
//! head disc). [`crate::mesh`] turns them into a graded size field.
//!
//! Exact integrals ([`Shape::moments`]) use Green's theorem along the exact curves, e.g.
//! `A = ½ ∮ (x dy − y dx)`, so they reproduce the reference values in closed form.

mod curve;
mod pendulum;
mod shape;

pub use curve::{segment_distance, Curve};
pub use pendulum::{check_parameters, pendulum};
pub use shape::{Corner, Edge, Moments, RegionSize, Shape, Solid};

/// A 2-D point `[x, y]` \[m\].
pub type Point = [f64; 2];

/// Name of the hinge edge.
pub const ROTATION: &str = "rotation";
/// Name of the outer head circle.
pub const CONTACT_HEAD: &str = "contact_head";
/// Name of every other boundary piece.
pub const DEFAULT: &str = "default";
/// Name of the region.
pub const PENDULUM: &str = "pendulum";
