//! Shapes and their booleans: boundary [`Edge`]s with names and sizes, the point-membership
//! tree [`Solid`], region and corner sizes, union/difference cut on the boundary, rotation, and
//! the exact [`Moments`] by Green's theorem.

use super::curve::{cross, dist, rotate, segment_distance, sub};
use super::{Curve, Point, DEFAULT};
use std::f64::consts::PI;

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
