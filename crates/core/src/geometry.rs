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

use crate::config::{Geometry, MeshSizes};
use crate::Error;
use std::f64::consts::PI;

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

/// A boundary curve, parametrised by `t ∈ [0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Curve {
    /// Straight segment from `a` to `b`: `p(t) = a + t (b − a)`.
    Line {
        /// Start.
        a: Point,
        /// End.
        b: Point,
    },
    /// Circular arc `p(t) = c + ρ (cos φ, sin φ)`, `φ = start + t · sweep` (sweep > 0: counter-clockwise).
    Arc {
        /// Centre.
        center: Point,
        /// Radius ρ.
        radius: f64,
        /// Start angle \[rad\].
        start: f64,
        /// Signed sweep \[rad\], |sweep| ≤ 2π.
        sweep: f64,
    },
}

impl Curve {
    /// The point at parameter `t`.
    pub fn point(&self, t: f64) -> Point {
        match *self {
            Curve::Line { a, b } => [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
            Curve::Arc {
                center,
                radius,
                start,
                sweep,
            } => {
                let phi = start + t * sweep;
                [center[0] + radius * phi.cos(), center[1] + radius * phi.sin()]
            }
        }
    }

    /// Unit tangent times the speed `|dp/dt|` at `t`.
    pub fn derivative(&self, t: f64) -> Point {
        match *self {
            Curve::Line { a, b } => [b[0] - a[0], b[1] - a[1]],
            Curve::Arc {
                radius, start, sweep, ..
            } => {
                let phi = start + t * sweep;
                [-radius * sweep * phi.sin(), radius * sweep * phi.cos()]
            }
        }
    }

    /// Arc length.
    pub fn length(&self) -> f64 {
        match *self {
            Curve::Line { a, b } => dist(a, b),
            Curve::Arc { radius, sweep, .. } => radius * sweep.abs(),
        }
    }

    /// The same curve traversed backwards.
    pub fn reversed(&self) -> Curve {
        match *self {
            Curve::Line { a, b } => Curve::Line { a: b, b: a },
            Curve::Arc {
                center,
                radius,
                start,
                sweep,
            } => Curve::Arc {
                center,
                radius,
                start: start + sweep,
                sweep: -sweep,
            },
        }
    }

    /// The piece between parameters `t0 < t1`.
    pub fn sub(&self, t0: f64, t1: f64) -> Curve {
        match *self {
            Curve::Line { .. } => Curve::Line {
                a: self.point(t0),
                b: self.point(t1),
            },
            Curve::Arc {
                center,
                radius,
                start,
                sweep,
            } => Curve::Arc {
                center,
                radius,
                start: start + t0 * sweep,
                sweep: (t1 - t0) * sweep,
            },
        }
    }

    /// The curve rotated by `angle` about `pivot`.
    pub fn rotated(&self, pivot: Point, angle: f64) -> Curve {
        match *self {
            Curve::Line { a, b } => Curve::Line {
                a: rotate(a, pivot, angle),
                b: rotate(b, pivot, angle),
            },
            Curve::Arc {
                center,
                radius,
                start,
                sweep,
            } => Curve::Arc {
                center: rotate(center, pivot, angle),
                radius,
                start: start + angle,
                sweep,
            },
        }
    }

    /// Euclidean distance from `p` to the curve.
    pub fn distance(&self, p: Point) -> f64 {
        match *self {
            Curve::Line { a, b } => segment_distance(p, a, b),
            Curve::Arc {
                center,
                radius,
                start,
                sweep,
            } => {
                let d = [p[0] - center[0], p[1] - center[1]];
                let r = (d[0] * d[0] + d[1] * d[1]).sqrt();
                if r > 0.0 && angle_param(d[1].atan2(d[0]), start, sweep).is_some() {
                    (r - radius).abs()
                } else {
                    dist(p, self.point(0.0)).min(dist(p, self.point(1.0)))
                }
            }
        }
    }

    /// Parameters `t ∈ [0, 1]` where this curve meets `other`, paired with the parameter on `other`.
    pub fn intersections(&self, other: &Curve) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        match (*self, *other) {
            (Curve::Line { a, b }, Curve::Line { a: c, b: d }) => {
                let r = sub(b, a);
                let s = sub(d, c);
                let den = cross(r, s);
                if den.abs() > 1e-14 * dot(r, r).max(dot(s, s)) {
                    let t = cross(sub(c, a), s) / den;
                    let u = cross(sub(c, a), r) / den;
                    if in_unit(t) && in_unit(u) {
                        out.push((t.clamp(0.0, 1.0), u.clamp(0.0, 1.0)));
                    }
                }
            }
            (Curve::Line { .. }, Curve::Arc { .. }) => {
                out = other.intersections(self).into_iter().map(|(u, t)| (t, u)).collect();
            }
            (
                Curve::Arc {
                    center,
                    radius,
                    start,
                    sweep,
                },
                Curve::Line { a, b },
            ) => {
                // |a + u (b − a) − c|² = ρ²
                let d = sub(b, a);
                let f = sub(a, center);
                let qa = dot(d, d);
                let qb = 2.0 * dot(f, d);
                let qc = dot(f, f) - radius * radius;
                let disc = qb * qb - 4.0 * qa * qc;
                if qa > 0.0 && disc >= 0.0 {
                    let sq = disc.sqrt();
                    for u in [(-qb - sq) / (2.0 * qa), (-qb + sq) / (2.0 * qa)] {
                        if in_unit(u) {
                            let p = sub(other.point(u.clamp(0.0, 1.0)), center);
                            if let Some(t) = angle_param(p[1].atan2(p[0]), start, sweep) {
                                out.push((t, u.clamp(0.0, 1.0)));
                            }
                        }
                    }
                }
            }
            (
                Curve::Arc {
                    center: c0,
                    radius: r0,
                    start: s0,
                    sweep: w0,
                },
                Curve::Arc {
                    center: c1,
                    radius: r1,
                    start: s1,
                    sweep: w1,
                },
            ) => {
                let d = sub(c1, c0);
                let dd = d[0].hypot(d[1]);
                if dd > 1e-14 * (r0 + r1) && dd <= r0 + r1 && dd >= (r0 - r1).abs() {
                    let along = (r0 * r0 - r1 * r1 + dd * dd) / (2.0 * dd);
                    let h = (r0 * r0 - along * along).max(0.0).sqrt();
                    let m = [c0[0] + along * d[0] / dd, c0[1] + along * d[1] / dd];
                    for sgn in [-1.0, 1.0] {
                        let p = [m[0] - sgn * h * d[1] / dd, m[1] + sgn * h * d[0] / dd];
                        let p0 = sub(p, c0);
                        let p1 = sub(p, c1);
                        if let (Some(t), Some(u)) = (
                            angle_param(p0[1].atan2(p0[0]), s0, w0),
                            angle_param(p1[1].atan2(p1[0]), s1, w1),
                        ) {
                            out.push((t, u));
                        }
                        if h == 0.0 {
                            break;
                        }
                    }
                }
            }
        }
        out
    }
}

/// One boundary piece: a curve, its boundary name and optional local mesh size.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    /// The exact curve, oriented with the region on the left.
    pub curve: Curve,
    /// Boundary name.
    pub name: String,
    /// Mesh size along this edge \[m\], if prescribed.
    pub size: Option<f64>,
}

/// Exact point membership.
#[derive(Clone, Debug, PartialEq)]
pub enum Solid {
    /// A convex polygon, vertices counter-clockwise.
    Polygon(Vec<Point>),
    /// A closed disc.
    Disc {
        /// Centre.
        center: Point,
        /// Radius.
        radius: f64,
    },
    /// Points in either.
    Union(Box<Solid>, Box<Solid>),
    /// Points in the first and not in the second.
    Difference(Box<Solid>, Box<Solid>),
}

impl Solid {
    /// Whether `p` is inside (points on the boundary count as inside for primitives).
    pub fn contains(&self, p: Point) -> bool {
        match self {
            Solid::Polygon(v) => (0..v.len()).all(|i| cross(sub(v[(i + 1) % v.len()], v[i]), sub(p, v[i])) >= 0.0),
            Solid::Disc { center, radius } => dist(p, *center) <= *radius,
            Solid::Union(a, b) => a.contains(p) || b.contains(p),
            Solid::Difference(a, b) => a.contains(p) && !b.contains(p),
        }
    }

    /// Distance from `p` to the set (0 inside). Exact for primitives; for unions the minimum,
    /// for differences the distance to the first operand (a lower bound).
    pub fn distance(&self, p: Point) -> f64 {
        match self {
            Solid::Polygon(v) => {
                if self.contains(p) {
                    0.0
                } else {
                    (0..v.len())
                        .map(|i| segment_distance(p, v[i], v[(i + 1) % v.len()]))
                        .fold(f64::INFINITY, f64::min)
                }
            }
            Solid::Disc { center, radius } => (dist(p, *center) - radius).max(0.0),
            Solid::Union(a, b) => a.distance(p).min(b.distance(p)),
            Solid::Difference(a, _) => a.distance(p),
        }
    }

    fn rotated(&self, pivot: Point, angle: f64) -> Solid {
        match self {
            Solid::Polygon(v) => Solid::Polygon(v.iter().map(|&q| rotate(q, pivot, angle)).collect()),
            Solid::Disc { center, radius } => Solid::Disc {
                center: rotate(*center, pivot, angle),
                radius: *radius,
            },
            Solid::Union(a, b) => Solid::Union(Box::new(a.rotated(pivot, angle)), Box::new(b.rotated(pivot, angle))),
            Solid::Difference(a, b) => {
                Solid::Difference(Box::new(a.rotated(pivot, angle)), Box::new(b.rotated(pivot, angle)))
            }
        }
    }
}

/// A region with a prescribed mesh size.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionSize {
    /// Label (e.g. "rod", "head").
    pub label: String,
    /// Where the size applies.
    pub solid: Solid,
    /// Mesh size inside \[m\].
    pub size: f64,
}

/// A point with a prescribed mesh size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// Location.
    pub point: Point,
    /// Mesh size at the point \[m\].
    pub size: f64,
}

/// A region bounded by lines and arcs, with names and local sizes.
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    /// Boundary pieces, region on the left.
    pub edges: Vec<Edge>,
    /// Exact membership.
    pub solid: Solid,
    /// Region sizes.
    pub regions: Vec<RegionSize>,
    /// Point sizes.
    pub corners: Vec<Corner>,
}

/// Area and moments of a shape, all exact integrals over the region.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moments {
    /// `A = ∫ dA` \[m²\].
    pub area: f64,
    /// `(∫ x dA, ∫ y dA)` \[m³\].
    pub first: Point,
    /// `∫ (x² + y²) dA` about the origin \[m⁴\].
    pub polar: f64,
}

impl Shape {
    /// The axis-aligned rectangle `[x0, x1] × [y0, y1]`, edges named "default" (bottom, right, top, left).
    pub fn rectangle(x0: f64, y0: f64, x1: f64, y1: f64) -> Shape {
        let c = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
        let edges = (0..4)
            .map(|i| Edge {
                curve: Curve::Line {
                    a: c[i],
                    b: c[(i + 1) % 4],
                },
                name: DEFAULT.into(),
                size: None,
            })
            .collect();
        Shape {
            edges,
            solid: Solid::Polygon(c.to_vec()),
            regions: Vec::new(),
            corners: Vec::new(),
        }
    }

    /// The disc of the given centre and radius, its circle one counter-clockwise edge named "default".
    pub fn circle(center: Point, radius: f64) -> Shape {
        let curve = Curve::Arc {
            center,
            radius,
            start: 0.0,
            sweep: 2.0 * PI,
        };
        Shape {
            edges: vec![Edge {
                curve,
                name: DEFAULT.into(),
                size: None,
            }],
            solid: Solid::Disc { center, radius },
            regions: Vec::new(),
            corners: Vec::new(),
        }
    }

    /// Names every edge and sets its size.
    pub fn with_edges(mut self, name: &str, size: Option<f64>) -> Shape {
        for e in &mut self.edges {
            e.name = name.into();
            e.size = size;
        }
        self
    }

    /// Gives the whole shape a region size.
    pub fn with_region_size(mut self, label: &str, size: f64) -> Shape {
        self.regions.push(RegionSize {
            label: label.into(),
            solid: self.solid.clone(),
            size,
        });
        self
    }

    /// `self ∪ other`.
    pub fn union(self, other: Shape) -> Shape {
        let (pa, pb) = split_pieces(&self.edges, &other.edges);
        let mut edges: Vec<Edge> = pa
            .into_iter()
            .filter(|e| !other.solid.contains(e.curve.point(0.5)))
            .collect();
        edges.extend(pb.into_iter().filter(|e| !self.solid.contains(e.curve.point(0.5))));
        let mut regions = self.regions;
        regions.extend(other.regions);
        let mut corners = self.corners;
        corners.extend(other.corners);
        Shape {
            edges,
            solid: Solid::Union(Box::new(self.solid), Box::new(other.solid)),
            regions,
            corners,
        }
    }

    /// `self − other`.
    pub fn difference(self, other: Shape) -> Shape {
        let (pa, pb) = split_pieces(&self.edges, &other.edges);
        let mut edges: Vec<Edge> = pa
            .into_iter()
            .filter(|e| !other.solid.contains(e.curve.point(0.5)))
            .collect();
        edges.extend(
            pb.into_iter()
                .filter(|e| self.solid.contains(e.curve.point(0.5)))
                .map(|mut e| {
                    e.curve = e.curve.reversed();
                    e
                }),
        );
        let mut corners = self.corners;
        corners.extend(other.corners);
        Shape {
            edges,
            solid: Solid::Difference(Box::new(self.solid), Box::new(other.solid)),
            regions: self.regions,
            corners,
        }
    }

    /// The shape rotated by `angle` \[rad\] counter-clockwise about `pivot`.
    pub fn rotated(self, pivot: Point, angle: f64) -> Shape {
        Shape {
            edges: self
                .edges
                .into_iter()
                .map(|e| Edge {
                    curve: e.curve.rotated(pivot, angle),
                    ..e
                })
                .collect(),
            solid: self.solid.rotated(pivot, angle),
            regions: self
                .regions
                .into_iter()
                .map(|r| RegionSize {
                    solid: r.solid.rotated(pivot, angle),
                    ..r
                })
                .collect(),
            corners: self
                .corners
                .into_iter()
                .map(|c| Corner {
                    point: rotate(c.point, pivot, angle),
                    size: c.size,
                })
                .collect(),
        }
    }

    /// Exact area, first and polar moments by Green's theorem along the exact curves.
    ///
    /// `A = ½∮(x dy − y dx)`, `∫x dA = ½∮x² dy`, `∫y dA = −½∮y² dx`,
    /// `∫(x² + y²) dA = ⅓∮(x³ dy − y³ dx)`; each curve is integrated with Gauss–Legendre on
    /// pieces of at most π/8 of arc (polynomial of degree 3 on lines: exact).
    pub fn moments(&self) -> Moments {
        let mut m = Moments {
            area: 0.0,
            first: [0.0, 0.0],
            polar: 0.0,
        };
        for e in &self.edges {
            let pieces = match e.curve {
                Curve::Line { .. } => 1,
                Curve::Arc { sweep, .. } => ((sweep.abs() / (PI / 8.0)).ceil() as usize).max(1),
            };
            for k in 0..pieces {
                let (t0, t1) = (k as f64 / pieces as f64, (k + 1) as f64 / pieces as f64);
                for (xi, w) in GAUSS_10 {
                    let t = t0 + (t1 - t0) * xi;
                    let w = w * (t1 - t0);
                    let [x, y] = e.curve.point(t);
                    let [dx, dy] = e.curve.derivative(t);
                    m.area += w * 0.5 * (x * dy - y * dx);
                    m.first[0] += w * 0.5 * x * x * dy;
                    m.first[1] -= w * 0.5 * y * y * dx;
                    m.polar += w * (x * x * x * dy - y * y * y * dx) / 3.0;
                }
            }
        }
        m
    }

    /// Names present on the boundary, in order of first appearance.
    pub fn boundary_names(&self) -> Vec<String> {
        let mut names: Vec<String> = Vec::new();
        for e in &self.edges {
            if !names.contains(&e.name) {
                names.push(e.name.clone());
            }
        }
        names
    }
}

/// Checks the pendulum parameters; each error names its parameter.
pub fn check_parameters(g: &Geometry, sizes: &MeshSizes) -> Result<(), Error> {
    let positive = |name: &str, v: f64| {
        if v > 0.0 && v.is_finite() {
            Ok(())
        } else {
            Err(Error::Geometry(format!("{name} = {v}: must be a finite value > 0 m")))
        }
    };
    positive("geometry.rod_half_width", g.rod_half_width)?;
    positive("geometry.head_radius", g.head_radius)?;
    positive("geometry.head_center_distance", g.head_center_distance)?;
    if !(g.hole_radius >= 0.0 && g.hole_radius.is_finite()) {
        return Err(Error::Geometry(format!(
            "geometry.hole_radius = {}: must be a finite value >= 0 m (0 = no hole)",
            g.hole_radius
        )));
    }
    if g.hole_radius >= g.head_radius {
        return Err(Error::Geometry(format!(
            "geometry.hole_radius = {}: the hole must lie inside the head (hole_radius < head_radius = {} m)",
            g.hole_radius, g.head_radius
        )));
    }
    if g.rod_half_width >= g.head_radius {
        return Err(Error::Geometry(format!(
            "geometry.rod_half_width = {}: the rod must be narrower than the head (rod_half_width < head_radius = {} m)",
            g.rod_half_width, g.head_radius
        )));
    }
    let reach = (g.head_radius * g.head_radius - g.rod_half_width * g.rod_half_width).sqrt();
    if g.head_center_distance <= reach {
        return Err(Error::Geometry(format!(
            "geometry.head_center_distance = {}: the rod is too short to reach the head with a free length \
             (need head_center_distance > sqrt(head_radius² − rod_half_width²) = {reach:.6} m)",
            g.head_center_distance
        )));
    }
    for (name, v) in [
        ("mesh.max_size", sizes.max_size),
        ("mesh.rod_size", sizes.rod),
        ("mesh.head_size", sizes.head),
        ("mesh.hinge_edge_size", sizes.hinge_edge),
        ("mesh.hinge_corner_size", sizes.hinge_corner),
        ("mesh.circle_edge_size", sizes.circle_edge),
    ] {
        positive(name, v)?;
    }
    if !(sizes.grading > 0.0 && sizes.grading.is_finite()) {
        return Err(Error::Geometry(format!(
            "mesh.grading = {}: must be a finite value > 0",
            sizes.grading
        )));
    }
    Ok(())
}

/// The pendulum as the tutorial builds it: rod `[−r, r] × [0, l]` ∪ head disc (centre `(0, l)`,
/// radius `R`) − hole (radius `r_hole`, none if 0), rotated 180° about the origin, so it hangs
/// in −y with the pivot at the origin and the hinge edge on `y = 0`.
///
/// Names: "rotation" (hinge edge, size `hinge_edge`), "contact_head" (outer head circle, size
/// `circle_edge`), "default" (rod sides and hole, the hole circle with size `circle_edge`).
/// Region sizes: rod `rod`, head disc `head`; corner sizes `hinge_corner` at `(±r, 0)`.
pub fn pendulum(g: &Geometry, sizes: &MeshSizes) -> Result<Shape, Error> {
    check_parameters(g, sizes)?;
    let (r, l, big_r) = (g.rod_half_width, g.head_center_distance, g.head_radius);
    let mut bar = Shape::rectangle(-r, 0.0, r, l).with_region_size("rod", sizes.rod);
    bar.edges[0].name = ROTATION.into();
    bar.edges[0].size = Some(sizes.hinge_edge);
    bar.corners.push(Corner {
        point: [-r, 0.0],
        size: sizes.hinge_corner,
    });
    bar.corners.push(Corner {
        point: [r, 0.0],
        size: sizes.hinge_corner,
    });
    let circ = Shape::circle([0.0, l], big_r)
        .with_edges(CONTACT_HEAD, Some(sizes.circle_edge))
        .with_region_size("head", sizes.head);
    let mut shape = circ.union(bar);
    if g.hole_radius > 0.0 {
        let hole = Shape::circle([0.0, l], g.hole_radius).with_edges(DEFAULT, Some(sizes.circle_edge));
        shape = shape.difference(hole);
    }
    Ok(shape.rotated([0.0, 0.0], PI))
}

/// Gauss–Legendre points on `[0, 1]` and weights (10 points, exact to degree 19).
const GAUSS_10: [(f64, f64); 10] = {
    const X: [f64; 5] = [
        0.148_874_338_981_631_2,
        0.433_395_394_129_247_2,
        0.679_409_568_299_024_4,
        0.865_063_366_688_984_5,
        0.973_906_528_517_171_7,
    ];
    const W: [f64; 5] = [
        0.295_524_224_714_752_9,
        0.269_266_719_309_996_4,
        0.219_086_362_515_982_04,
        0.149_451_349_150_580_6,
        0.066_671_344_308_688_14,
    ];
    let mut out = [(0.0, 0.0); 10];
    let mut i = 0;
    while i < 5 {
        out[2 * i] = (0.5 - 0.5 * X[i], 0.5 * W[i]);
        out[2 * i + 1] = (0.5 + 0.5 * X[i], 0.5 * W[i]);
        i += 1;
    }
    out
};

/// Cuts both edge lists at their mutual intersections.
fn split_pieces(a: &[Edge], b: &[Edge]) -> (Vec<Edge>, Vec<Edge>) {
    let mut ta: Vec<Vec<f64>> = vec![Vec::new(); a.len()];
    let mut tb: Vec<Vec<f64>> = vec![Vec::new(); b.len()];
    for (i, ea) in a.iter().enumerate() {
        for (j, eb) in b.iter().enumerate() {
            for (t, u) in ea.curve.intersections(&eb.curve) {
                ta[i].push(t);
                tb[j].push(u);
            }
        }
    }
    (cut(a, ta), cut(b, tb))
}

fn cut(edges: &[Edge], params: Vec<Vec<f64>>) -> Vec<Edge> {
    let mut out = Vec::new();
    for (e, mut ts) in edges.iter().zip(params) {
        let closed = matches!(e.curve, Curve::Arc { sweep, .. } if (sweep.abs() - 2.0 * PI).abs() < 1e-12);
        if closed {
            // Cuts at the start point of a full circle are real cuts; 1 is the same point as 0.
            ts = ts.into_iter().map(|t| if t > 1.0 - 1e-10 { 0.0 } else { t }).collect();
        } else {
            ts.retain(|&t| t > 1e-10 && t < 1.0 - 1e-10);
        }
        ts.sort_by(f64::total_cmp);
        ts.dedup_by(|x, y| (*x - *y).abs() < 1e-10);
        if closed && !ts.is_empty() {
            // A full circle: pieces run from cut to cut, the last one wrapping past the start.
            let first = ts[0];
            for k in 0..ts.len() {
                let end = if k + 1 < ts.len() { ts[k + 1] } else { first + 1.0 };
                out.push(Edge {
                    curve: e.curve.sub(ts[k], end),
                    ..e.clone()
                });
            }
            continue;
        }
        let mut prev = 0.0;
        for t in ts.into_iter().chain([1.0]) {
            out.push(Edge {
                curve: e.curve.sub(prev, t),
                ..e.clone()
            });
            prev = t;
        }
    }
    out
}

/// Parameter of angle `phi` on an arc starting at `start` with signed `sweep`, if on the arc.
fn angle_param(phi: f64, start: f64, sweep: f64) -> Option<f64> {
    let rel = if sweep >= 0.0 { phi - start } else { start - phi };
    let rel = rel.rem_euclid(2.0 * PI);
    let w = sweep.abs();
    let eps = 1e-12;
    if rel <= w + eps {
        Some((rel / w).min(1.0))
    } else if 2.0 * PI - rel < eps {
        Some(0.0)
    } else {
        None
    }
}

fn in_unit(t: f64) -> bool {
    (-1e-12..=1.0 + 1e-12).contains(&t)
}

fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1]]
}

fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn cross(a: Point, b: Point) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn dist(a: Point, b: Point) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

fn rotate(p: Point, pivot: Point, angle: f64) -> Point {
    // Exact for multiples of 90° (sin π is 1.2e-16 in floating point, not 0).
    let snap = |v: f64| if v.abs() < 1e-15 { 0.0 } else { v };
    let (s, c) = angle.sin_cos();
    let (s, c) = (snap(s), snap(c));
    let d = sub(p, pivot);
    [pivot[0] + c * d[0] - s * d[1], pivot[1] + s * d[0] + c * d[1]]
}

/// Distance from `p` to the segment `a b`.
pub fn segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let t = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, [a[0] + t * ab[0], a[1] + t * ab[1]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_param_handles_wraparound_and_negative_sweeps() {
        assert_eq!(angle_param(0.5, 0.0, 1.0), Some(0.5));
        assert!(angle_param(-0.5, 0.0, 1.0).is_none());
        assert!((angle_param(-0.5, 0.0, -1.0).unwrap() - 0.5).abs() < 1e-15);
        assert!((angle_param(-3.0, 3.0, 1.0).unwrap() - (2.0 * PI - 6.0)).abs() < 1e-12);
    }
}
