//! Delaunay refinement (Ruppert/Chew style) of a constrained Delaunay triangulation with curved
//! boundary segments and a size field.
//!
//! Input: boundary points and segments, each segment knowing the exact curve it discretises and
//! its parameter interval `[t_a, t_b]`, oriented with the domain on its left.
//!
//! Loop (segments first, then triangles):
//!
//! 1. A segment is *encroached* if the apex of its inside triangle lies strictly inside its
//!    diametral circle. It is split at its parameter midpoint `t_m = (t_a + t_b)/2`, which lies
//!    exactly on the curve (the arc midpoint for arcs): the chord constraint is removed, the point
//!    inserted and the two sub-chords constrained.
//! 2. An inside triangle is *bad* if its minimum angle is below the quality bound or its longest
//!    edge exceeds `size_factor · h(centroid)`. Its circumcentre `c` is inserted unless `c` lies in
//!    the diametral circle of any segment (found through a uniform grid over the segments) or the
//!    straight walk from the triangle to `c` crosses a segment; in both cases that segment is split
//!    instead and the triangle retried.
//!
//! Faces are tracked by handle plus vertex triple; a queued face whose triple changed is stale and
//! skipped. Inside/outside is decided by parity of constraint crossings from the outer face (flood
//! fill, so the hole is outside); after every pass the whole triangulation is reclassified and
//! re-checked, and the loop ends when a pass inserts nothing. Ruppert's analysis guarantees
//! termination for quality bounds up to about 20.7° with input angles ≥ 60°; in practice (and
//! for the pendulum, whose input angles are 90° or reflex) bounds near 30° terminate. A vertex cap
//! turns non-termination into an error.

use std::collections::{HashMap, VecDeque};

use spade::handles::{FixedFaceHandle, FixedVertexHandle, InnerTag};
use spade::{ConstrainedDelaunayTriangulation, Point2, PositionInTriangulation, Triangulation};

use super::size::SizeField;
use crate::error::Error;
use crate::geometry::{Curve, Point};

pub(crate) type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// A boundary segment: a chord of `curve` between parameters `ta` and `tb`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Segment {
    pub a: u32,
    pub b: u32,
    /// Index of the geometry edge.
    pub edge: u32,
    pub ta: f64,
    pub tb: f64,
    pub alive: bool,
}

/// Refinement settings.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Settings {
    /// Minimum-angle bound \[deg\].
    pub min_angle_deg: f64,
    /// A triangle is too big if its longest edge exceeds `size_factor · h(centroid)`.
    pub size_factor: f64,
}

pub(crate) struct Refiner<'a> {
    pub cdt: Cdt,
    pub segs: Vec<Segment>,
    seg_of: HashMap<(u32, u32), u32>,
    grid: SegGrid,
    curves: &'a [Curve],
    size: &'a SizeField,
    faces: VecDeque<(FixedFaceHandle<InnerTag>, [u32; 3])>,
    seg_queue: Vec<u32>,
    sin_min: f64,
    size_factor: f64,
    max_vertices: usize,
    min_seg_len: f64,
}

fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

fn p2(p: Point) -> Point2<f64> {
    Point2::new(p[0], p[1])
}

fn orient(p: Point2<f64>, q: Point2<f64>, r: Point2<f64>) -> f64 {
    (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x)
}

fn d2(p: Point2<f64>, q: Point2<f64>) -> f64 {
    (p.x - q.x).powi(2) + (p.y - q.y).powi(2)
}

fn encroaches(a: Point2<f64>, b: Point2<f64>, p: Point2<f64>) -> bool {
    let m = Point2::new(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
    d2(p, m) < 0.25 * d2(a, b) * (1.0 - 1e-9)
}

enum Walk {
    Reached(FixedVertexHandle),
    Blocked(u32, u32),
    Degenerate,
}

impl<'a> Refiner<'a> {
    /// Triangulates the boundary: `segments` are `(a, b, edge, ta, tb)` with point indices.
    pub fn new(
        points: &[Point],
        segments: &[(usize, usize, usize, f64, f64)],
        curves: &'a [Curve],
        size: &'a SizeField,
        settings: Settings,
        max_vertices: usize,
    ) -> Result<Self, Error> {
        let mut cdt = Cdt::new();
        for (i, p) in points.iter().enumerate() {
            let h = cdt
                .insert(p2(*p))
                .map_err(|e| Error::Mesh(format!("boundary point {p:?} could not be inserted: {e:?}")))?;
            if h.index() != i {
                return Err(Error::Mesh(format!(
                    "boundary point {p:?} coincides with another boundary point"
                )));
            }
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let mut lens: Vec<f64> = segments
            .iter()
            .map(|s| (points[s.0][0] - points[s.1][0]).hypot(points[s.0][1] - points[s.1][1]))
            .collect();
        lens.sort_by(f64::total_cmp);
        let median = lens.get(lens.len() / 2).copied().unwrap_or(1.0);
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
        let cell = median
            .max(((hi[0] - lo[0]) * (hi[1] - lo[1]) / 262_144.0).sqrt())
            .max(extent * 1e-6);
        let grid = SegGrid::new(lo, hi, cell);
        let mut r = Refiner {
            cdt,
            segs: Vec::with_capacity(segments.len() * 2),
            seg_of: HashMap::with_capacity(segments.len() * 2),
            grid,
            curves,
            size,
            faces: VecDeque::new(),
            seg_queue: Vec::new(),
            sin_min: settings.min_angle_deg.to_radians().sin(),
            size_factor: settings.size_factor,
            max_vertices,
            min_seg_len: extent * 1e-9,
        };
        for &(a, b, edge, ta, tb) in segments {
            let added = r
                .cdt
                .try_add_constraint(FixedVertexHandle::from_index(a), FixedVertexHandle::from_index(b));
            if added.len() != 1 {
                return Err(Error::Mesh(format!(
                    "boundary segment {:?}–{:?} crosses another boundary segment or passes through a boundary point",
                    points[a], points[b]
                )));
            }
            r.add_segment(a as u32, b as u32, edge as u32, ta, tb);
        }
        Ok(r)
    }

    fn pos(&self, v: u32) -> Point2<f64> {
        self.cdt.vertex(FixedVertexHandle::from_index(v as usize)).position()
    }

    fn add_segment(&mut self, a: u32, b: u32, edge: u32, ta: f64, tb: f64) -> u32 {
        let id = self.segs.len() as u32;
        self.segs.push(Segment {
            a,
            b,
            edge,
            ta,
            tb,
            alive: true,
        });
        self.seg_of.insert(key(a, b), id);
        let (pa, pb) = (self.pos(a), self.pos(b));
        self.grid.insert(id, pa, pb);
        self.seg_queue.push(id);
        id
    }

    /// The segment between two vertices, if any.
    pub fn segment_between(&self, a: u32, b: u32) -> Option<&Segment> {
        self.seg_of.get(&key(a, b)).map(|&i| &self.segs[i as usize])
    }

    /// Inside flag per face index (parity of constraint crossings from the outer face).
    pub fn classify(&self) -> Vec<bool> {
        let n = self.cdt.num_all_faces();
        let mut state = vec![u8::MAX; n];
        let mut queue = VecDeque::new();
        for f in self.cdt.inner_faces() {
            for e in f.adjacent_edges() {
                if e.rev().face().is_outer() && state[f.fix().index()] == u8::MAX {
                    state[f.fix().index()] = e.is_constraint_edge() as u8;
                    queue.push_back(f.fix());
                }
            }
        }
        while let Some(f) = queue.pop_front() {
            let s = state[f.index()];
            for e in self.cdt.face(f).adjacent_edges() {
                if let Some(g) = e.rev().face().as_inner() {
                    let gi = g.fix().index();
                    if state[gi] == u8::MAX {
                        state[gi] = s ^ (e.is_constraint_edge() as u8);
                        queue.push_back(g.fix());
                    }
                }
            }
        }
        state.into_iter().map(|s| s == 1).collect()
    }

    fn triple(&self, f: FixedFaceHandle<InnerTag>) -> [u32; 3] {
        self.cdt.face(f).vertices().map(|v| v.fix().index() as u32)
    }

    fn push_face(&mut self, f: FixedFaceHandle<InnerTag>) {
        let t = self.triple(f);
        self.faces.push_back((f, t));
    }

    /// Refines until no segment is encroached and no inside triangle is bad; returns the final
    /// inside flag per face index.
    pub fn run(&mut self) -> Result<Vec<bool>, Error> {
        for _pass in 0..20 {
            let before = self.cdt.num_vertices();
            let inside = self.classify();
            self.seg_queue = (0..self.segs.len() as u32)
                .filter(|&i| self.segs[i as usize].alive)
                .collect();
            let bad: Vec<_> = self
                .cdt
                .fixed_inner_faces()
                .filter(|f| inside[f.index()] && self.assess(*f).is_some())
                .collect();
            for f in bad {
                self.push_face(f);
            }
            self.process()?;
            if self.cdt.num_vertices() == before {
                // Nothing changed in this pass, so the classification is still current.
                return Ok(inside);
            }
        }
        Err(Error::Mesh("Delaunay refinement did not settle after 20 passes".into()))
    }

    fn process(&mut self) -> Result<(), Error> {
        loop {
            if self.cdt.num_vertices() > self.max_vertices {
                return Err(Error::Mesh(format!(
                    "Delaunay refinement exceeded {} vertices; the sizes are too small for this geometry",
                    self.max_vertices
                )));
            }
            if let Some(s) = self.seg_queue.pop() {
                if self.segs[s as usize].alive && self.is_encroached(s) {
                    self.split(s)?;
                }
                continue;
            }
            let Some((f, tri)) = self.faces.pop_front() else {
                return Ok(());
            };
            if self.triple(f) != tri {
                continue;
            }
            let Some((centroid, cc)) = self.assess(f) else {
                continue;
            };
            if let Some(s) = self.encroached_by(cc) {
                self.split(s)?;
                self.faces.push_back((f, tri));
                continue;
            }
            match self.walk(f, centroid, cc) {
                Walk::Degenerate => continue,
                Walk::Blocked(u, v) => {
                    let s = *self
                        .seg_of
                        .get(&key(u, v))
                        .ok_or_else(|| Error::Mesh("a constraint edge without a boundary segment".into()))?;
                    self.split(s)?;
                    self.faces.push_back((f, tri));
                }
                Walk::Reached(hint) => {
                    let n = self.cdt.num_vertices();
                    let v = self
                        .cdt
                        .insert_with_hint(cc, hint)
                        .map_err(|e| Error::Mesh(format!("inserting a Steiner point failed: {e:?}")))?;
                    if v.index() != n {
                        continue;
                    }
                    let star: Vec<_> = self
                        .cdt
                        .vertex(v)
                        .out_edges()
                        .filter_map(|e| e.face().fix().as_inner())
                        .collect();
                    for g in star {
                        self.push_face(g);
                    }
                }
            }
        }
    }

    /// For a bad triangle (too skinny or too big, and not tiny), its centroid and circumcentre.
    fn assess(&self, f: FixedFaceHandle<InnerTag>) -> Option<(Point2<f64>, Point2<f64>)> {
        let [a, b, c] = self.cdt.face(f).positions();
        let (la, lb, lc) = (d2(b, c).sqrt(), d2(c, a).sqrt(), d2(a, b).sqrt());
        let area2 = orient(a, b, c);
        let (short, l1, l2) = if la <= lb && la <= lc {
            (la, lb, lc)
        } else if lb <= lc {
            (lb, lc, la)
        } else {
            (lc, la, lb)
        };
        let longest = la.max(lb).max(lc);
        let centroid = Point2::new((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0);
        let skinny = area2 < self.sin_min * l1 * l2;
        let bad = skinny || longest > self.size_factor * self.size.at([centroid.x, centroid.y]);
        (bad && short >= self.min_seg_len).then(|| (centroid, circumcenter(a, b, c)))
    }

    fn is_encroached(&self, s: u32) -> bool {
        let seg = self.segs[s as usize];
        let (a, b) = (
            FixedVertexHandle::from_index(seg.a as usize),
            FixedVertexHandle::from_index(seg.b as usize),
        );
        let Some(e) = self.cdt.get_edge_from_neighbors(a, b) else {
            return false;
        };
        match e.opposite_vertex() {
            Some(v) => encroaches(e.from().position(), e.to().position(), v.position()),
            None => false,
        }
    }

    fn encroached_by(&self, p: Point2<f64>) -> Option<u32> {
        self.grid.query(p).iter().copied().find(|&s| {
            let seg = self.segs[s as usize];
            seg.alive && encroaches(self.pos(seg.a), self.pos(seg.b), p)
        })
    }

    /// Straight walk from `o` (inside face `f`) to `target`, stopping at constraint edges.
    fn walk(&self, f: FixedFaceHandle<InnerTag>, o: Point2<f64>, target: Point2<f64>) -> Walk {
        let mut face = self.cdt.face(f);
        for _ in 0..1_000_000 {
            let mut next = None;
            for e in face.adjacent_edges() {
                let [p, q] = e.positions();
                if orient(p, q, target) < 0.0 {
                    let (sp, sq) = (orient(o, target, p), orient(o, target, q));
                    if sp == 0.0 || sq == 0.0 {
                        return Walk::Degenerate;
                    }
                    if (sp > 0.0) != (sq > 0.0) {
                        next = Some(e);
                        break;
                    }
                }
            }
            match next {
                None => return Walk::Reached(face.vertices()[0].fix()),
                Some(e) => {
                    if e.is_constraint_edge() {
                        return Walk::Blocked(e.from().fix().index() as u32, e.to().fix().index() as u32);
                    }
                    match e.rev().face().as_inner() {
                        Some(g) => face = g,
                        None => return Walk::Degenerate,
                    }
                }
            }
        }
        Walk::Degenerate
    }

    /// Splits segment `s` at its parameter midpoint on the exact curve.
    fn split(&mut self, s: u32) -> Result<(), Error> {
        let seg = self.segs[s as usize];
        if !seg.alive {
            return Ok(());
        }
        let (pa, pb) = (self.pos(seg.a), self.pos(seg.b));
        if d2(pa, pb).sqrt() < self.min_seg_len {
            return Err(Error::Mesh(format!(
                "boundary segment near ({:.6}, {:.6}) became too short to split; the geometry is too thin for the sizes",
                pa.x, pa.y
            )));
        }
        let (a, b) = (
            FixedVertexHandle::from_index(seg.a as usize),
            FixedVertexHandle::from_index(seg.b as usize),
        );
        let edge = self
            .cdt
            .get_edge_from_neighbors(a, b)
            .ok_or_else(|| Error::Mesh("a boundary segment is missing from the triangulation".into()))?
            .as_undirected()
            .fix();
        self.segs[s as usize].alive = false;
        self.seg_of.remove(&key(seg.a, seg.b));
        self.grid.remove(s, pa, pb);
        self.cdt.remove_constraint_edge(edge);
        let tm = 0.5 * (seg.ta + seg.tb);
        let m = p2(self.curves[seg.edge as usize].point(tm));
        match self.cdt.locate_with_hint(m, a) {
            PositionInTriangulation::OnVertex(_) => {
                return Err(Error::Mesh(format!(
                    "boundary split point ({}, {}) hits an existing vertex",
                    m.x, m.y
                )))
            }
            PositionInTriangulation::OnEdge(e) if self.cdt.directed_edge(e).is_constraint_edge() => {
                return Err(Error::Mesh(format!(
                    "boundary split point ({}, {}) lies on another boundary segment; the geometry is too thin",
                    m.x, m.y
                )))
            }
            _ => {}
        }
        let n = self.cdt.num_vertices();
        let v = self
            .cdt
            .insert_with_hint(m, a)
            .map_err(|e| Error::Mesh(format!("inserting a boundary point failed: {e:?}")))?;
        if v.index() != n {
            return Err(Error::Mesh("a boundary split point coincides with a vertex".into()));
        }
        let vi = v.index() as u32;
        for (x, y) in [(a, v), (v, b)] {
            if self.cdt.try_add_constraint(x, y).len() != 1 {
                return Err(Error::Mesh(format!(
                    "boundary sub-segment at ({:.6}, {:.6}) crosses another segment; the geometry is too thin for the sizes",
                    m.x, m.y
                )));
            }
        }
        self.add_segment(seg.a, vi, seg.edge, seg.ta, tm);
        self.add_segment(vi, seg.b, seg.edge, tm, seg.tb);
        // Faces around the new vertex: inside iff counter-clockwise between the out-edges to b and a.
        let fwd = (pb.y - m.y).atan2(pb.x - m.x);
        let rel = |p: Point2<f64>| ((p.y - m.y).atan2(p.x - m.x) - fwd).rem_euclid(std::f64::consts::TAU);
        let back = rel(pa);
        let star: Vec<_> = self
            .cdt
            .vertex(v)
            .out_edges()
            .filter_map(|e| {
                let r = rel(e.to().position());
                e.face().fix().as_inner().filter(|_| r < back - 1e-12)
            })
            .collect();
        for g in star {
            self.push_face(g);
        }
        let near: Vec<u32> = self.grid.query(m).to_vec();
        self.seg_queue
            .extend(near.into_iter().filter(|&t| self.segs[t as usize].alive));
        Ok(())
    }
}

fn circumcenter(a: Point2<f64>, b: Point2<f64>, c: Point2<f64>) -> Point2<f64> {
    let (bx, by) = (b.x - a.x, b.y - a.y);
    let (cx, cy) = (c.x - a.x, c.y - a.y);
    let d = 2.0 * (bx * cy - by * cx);
    let b2 = bx * bx + by * by;
    let c2 = cx * cx + cy * cy;
    Point2::new(a.x + (cy * b2 - by * c2) / d, a.y + (bx * c2 - cx * b2) / d)
}

/// Uniform grid of segment ids, each registered in every cell its diametral circle's box touches.
struct SegGrid {
    lo: Point,
    cell: f64,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<u32>>,
}

impl SegGrid {
    fn new(lo: Point, hi: Point, cell: f64) -> Self {
        let nx = (((hi[0] - lo[0]) / cell).ceil() as usize).max(1);
        let ny = (((hi[1] - lo[1]) / cell).ceil() as usize).max(1);
        Self {
            lo,
            cell,
            nx,
            ny,
            cells: vec![Vec::new(); nx * ny],
        }
    }

    fn index(&self, x: f64, y: f64) -> (usize, usize) {
        let i = ((x - self.lo[0]) / self.cell).floor().clamp(0.0, (self.nx - 1) as f64) as usize;
        let j = ((y - self.lo[1]) / self.cell).floor().clamp(0.0, (self.ny - 1) as f64) as usize;
        (i, j)
    }

    fn range(&self, a: Point2<f64>, b: Point2<f64>) -> ((usize, usize), (usize, usize)) {
        let m = [0.5 * (a.x + b.x), 0.5 * (a.y + b.y)];
        let r = 0.5 * d2(a, b).sqrt();
        (self.index(m[0] - r, m[1] - r), self.index(m[0] + r, m[1] + r))
    }

    fn insert(&mut self, id: u32, a: Point2<f64>, b: Point2<f64>) {
        let ((i0, j0), (i1, j1)) = self.range(a, b);
        for j in j0..=j1 {
            for i in i0..=i1 {
                self.cells[j * self.nx + i].push(id);
            }
        }
    }

    fn remove(&mut self, id: u32, a: Point2<f64>, b: Point2<f64>) {
        let ((i0, j0), (i1, j1)) = self.range(a, b);
        for j in j0..=j1 {
            for i in i0..=i1 {
                self.cells[j * self.nx + i].retain(|&s| s != id);
            }
        }
    }

    fn query(&self, p: Point2<f64>) -> &[u32] {
        let (i, j) = self.index(p.x, p.y);
        &self.cells[j * self.nx + i]
    }
}
