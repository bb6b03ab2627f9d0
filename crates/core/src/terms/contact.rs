//! Contact of the head with a rigid wall, the half-plane `x ≤ x_w`, as a penalty energy on the
//! head's arc (the boundary named `contact_head`).
//!
//! At the Gauss points `q` of every curved edge of the arc (reference arc length and thickness in
//! the weight `w_q = ds · t` \[m²\]), the signed gap to the wall face is
//!
//! ```text
//! g_q(u) = x_q − x_w = Σ_a N_a (X_a + u_a,x) − x_w        [m]   (negative: penetration)
//! ```
//!
//! linear in `u`, and the contact energy is `k/2` times the squared penetration per unit area,
//!
//! ```text
//! Π_c = Σ_q w_q ψ(g_q),   ψ(g) = ½ k min(g, 0)²                     [J]
//! ∂Π_c/∂u_a,x = Σ_q w_q k min(g_q, 0) N_a,   ∂²Π_c/∂u_a,x ∂u_b,x = Σ_q w_q k [g_q < 0] N_a N_b
//! ```
//!
//! with `k` the normal pressure per unit penetration \[N/m³\] (`contact.stiffness`). The wall pushes
//! only in `+x`; it is frictionless.
//!
//! **Discrete gradient.** Since `g_q` is linear in `u`, the secant of `ψ` along each point's gap,
//! `ψ_d = (ψ(g₁) − ψ(g₀))/(g₁ − g₀)` (`ψ'(g)` when `g₁ = g₀`), gives `∇ᵈΠ_c · Δu = Π_c(u₁) − Π_c(u₀)`
//! exactly: the contact force over a step does exactly the work of the change of contact energy,
//! so an impact neither gains nor loses energy (Armero & Petocz 1998; Laursen & Chawla 1997). Both
//! ends penetrating, the secant is `½ k (g₀ + g₁)`, free of cancellation; both apart, 0.
//!
//! The Hessian entries couple the nodes of one edge, which lie in one element: they are in the
//! element pattern, and the term writes them (zeros when apart) without extra entries.
//!
//! **The deformable face** ([`WallContact::deformable`]) is the polyline through the block's face
//! nodes. A head point's gap is its distance in `x` to the face segment at its height; past the
//! face's ends the end segment's line is continued, and the energy fades out over one taper length
//! `ℓ` (the end segment's reference length) past the end with the smooth factor
//!
//! ```text
//! Π_c = Σ_q w_q ψ(g_q) s(η_q),   s(η) = 1 − 3η² + 2η³ on [0, 1], 1 below, 0 above,
//! η = (distance of the point past the face's nearer end) / ℓ        (≤ 0 on the face)
//! ```
//!
//! (a block's corner rounded over one face element), so that the energy is continuous, with a
//! continuous gradient, where a point leaves the face. The discrete gradient of each point's
//! `ψ(g) s(η)` is the product rule for secants,
//! `½(s₀ + s₁) ψ_d ∇ᵈg + ½(ψ₀ + ψ₁) s_d ∇ᵈη`, with `ψ_d`, `s_d` the secants of `ψ` and `s` between the
//! step's ends and `∇ᵈg`, `∇ᵈη` the mid-step gradients corrected along `Δu` so that
//! `∇ᵈg · Δu = g₁ − g₀` and `∇ᵈη · Δu = η₁ − η₀` exactly, for the gaps and heights of both ends on
//! their own segments: the discrete-gradient identity holds to rounding whatever segments or
//! ends the point crosses within the step.
//!
//! **Behind the block.** A point deeper than the pattern's margin (`reach`, below) behind the
//! face's line has no energy (its `η` is set beyond the taper): it is behind the block, where the
//! face is no contact surface. Without that cut, a head that swung over the pivot and down past
//! the block's far side, 0.1 m behind the face and nowhere near the block, bounced off the
//! face's line continued wherever its arc passed within one taper length of the face's ends. A
//! head that comes round the face's end onto the block itself is outside the model
//! ([`WallContact::behind_face`]).
//!
//! **Its Hessian pattern.** A head point can only touch the face at a height fixed by its distance
//! `r` from the pivot: turning rigidly about the pivot, it meets the plane `x = x_w` at
//! `y = ±√(r² − x_w²)`. The pattern couples every head edge with the face segments within that band
//! of heights, widened by a deformation margin (`reach`: the radius, the face's position and the
//! segment's ends may move by that much): every pair that can touch when the bodies deform by less
//! than the margin. A contact outside the coupled pairs (a larger deformation) is reported by
//! [`WallContact::uncoupled_contact`], and the simulation stops with an error naming it rather than
//! drop the stiffness.

use super::{StepContext, StepStart, Term};
use crate::assembly::Pattern;
use crate::element::Tri6;
use crate::quadrature::gauss_legendre_unit;
use crate::{Error, Mesh};

/// One quadrature point of the contact arc.
#[derive(Clone, Debug)]
struct ContactPoint {
    /// The edge's `[start, end, mid]` nodes.
    nodes: [usize; 3],
    /// The edge's index among the arc's edges.
    edge: usize,
    /// The quadratic edge basis at the point.
    basis: [f64; 3],
    /// Reference `x` of the point \[m\].
    x_ref: f64,
    /// Reference `y` of the point \[m\].
    y_ref: f64,
    /// Reference arc length times thickness \[m²\].
    weight: f64,
}

/// The deformable wall's face: the nodes of its contact edge, sorted by reference `y`, as a
/// polyline (straight pieces between consecutive nodes).
#[derive(Clone, Debug)]
struct Face {
    nodes: Vec<usize>,
    /// Taper lengths `ℓ` past the bottom and the top end: the end segments' reference lengths \[m\].
    taper: [f64; 2],
    /// The `(head edge, face segment)` pairs that the Hessian pattern couples, sorted.
    pairs: Vec<(usize, usize)>,
    /// The deformation margin of the pairs \[m\].
    reach: f64,
}

/// A point's gap and its gradient over its local degrees of freedom; with the face also its
/// height past the face's nearer end in taper lengths and the gradient of that.
struct Local {
    g: f64,
    /// `η` (≤ 0 on the face; −1 for the rigid wall).
    eta: f64,
    dofs: [usize; 10],
    grad: [f64; 10],
    deta: [f64; 10],
    n: usize,
    /// The face segment used.
    seg: usize,
}

impl Local {
    /// `values += c ∇g ∇gᵀ` in the upper triangle of `pattern`. Pairs outside the pattern occur
    /// only on the deformable face (beyond its coupled pairs), where
    /// [`WallContact::uncoupled_contact`] stops the step after it; they are skipped.
    fn add_outer(&self, c: f64, pattern: &Pattern, values: &mut [f64]) {
        for i in 0..self.n {
            for j in 0..self.n {
                let (r, col) = (self.dofs[i], self.dofs[j]);
                if r > col {
                    continue;
                }
                if let Some(pos) = pattern.position(r, col) {
                    values[pos] += c * self.grad[i] * self.grad[j];
                }
            }
        }
    }
}

/// The taper `s(η)` of the face's ends (see the module doc).
fn taper(eta: f64) -> f64 {
    let e = eta.clamp(0.0, 1.0);
    1.0 - e * e * (3.0 - 2.0 * e)
}

/// `s'(η)`.
fn taper_slope(eta: f64) -> f64 {
    let e = eta.clamp(0.0, 1.0);
    -6.0 * e * (1.0 - e)
}

/// The secant of `s` between `e0` and `e1` (`s'` when they coincide), in closed form on one piece.
fn taper_secant(e0: f64, e1: f64) -> f64 {
    let (c0, c1) = (e0.clamp(0.0, 1.0), e1.clamp(0.0, 1.0));
    if c0 == c1 {
        return if e0 == e1 { taper_slope(e0) } else { 0.0 };
    }
    if (c0 == e0) && (c1 == e1) {
        // both on the cubic: (s1 − s0)/(e1 − e0) without cancellation
        return -3.0 * (e0 + e1) + 2.0 * (e0 * e0 + e0 * e1 + e1 * e1);
    }
    (taper(e1) - taper(e0)) / (e1 - e0)
}

/// The contact of the named boundary with a wall whose face is `x = x_w` (see the module doc): a
/// rigid half-plane `x ≤ x_w`, or the face of a deformable body ([`WallContact::deformable`]).
#[derive(Clone, Debug)]
pub struct WallContact {
    /// `x_w`, the wall's face \[m\].
    pub face_x: f64,
    /// `k` \[N/m³\].
    pub stiffness: f64,
    /// `true`: the force of a step is the penalty force at its end, `∇Π_c(u₁)` (the tutorial's
    /// `contact.method = "penalty"`), not the secant; it does not conserve energy.
    pub end_point: bool,
    points: Vec<ContactPoint>,
    /// The deformable wall's face, if the wall is a body.
    face: Option<Face>,
    /// Reference coordinates of the mesh's nodes \[m\].
    reference: Vec<[f64; 2]>,
}

impl WallContact {
    /// The wall at `face_x` with stiffness `stiffness` against the boundary `name` of `mesh`, with
    /// `points_per_edge` Gauss points on every edge (exact arc geometry through the edge's three
    /// nodes) and the body's `thickness`.
    pub fn new(
        mesh: &Mesh,
        name: &str,
        face_x: f64,
        stiffness: f64,
        thickness: f64,
        points_per_edge: usize,
    ) -> Result<Self, Error> {
        let rule = gauss_legendre_unit(points_per_edge.max(1));
        let mut points = Vec::new();
        for (edge, e) in mesh.edges_named(name).enumerate() {
            let x = e.nodes.map(|n| mesh.nodes[n]);
            for &(s, w) in &rule {
                let n = Tri6::edge_basis(s);
                let dn = Tri6::edge_basis_derivatives(s);
                let dx = [0, 1].map(|i| (0..3).map(|a| dn[a] * x[a][i]).sum::<f64>());
                points.push(ContactPoint {
                    nodes: e.nodes,
                    edge,
                    basis: n,
                    x_ref: (0..3).map(|a| n[a] * x[a][0]).sum(),
                    y_ref: (0..3).map(|a| n[a] * x[a][1]).sum(),
                    weight: w * dx[0].hypot(dx[1]) * thickness,
                });
            }
        }
        if points.is_empty() {
            return Err(Error::Mesh(format!(
                "the mesh has no boundary named \"{name}\" for the contact with the wall"
            )));
        }
        Ok(Self {
            face_x,
            stiffness,
            end_point: false,
            points,
            face: None,
            reference: mesh.nodes.clone(),
        })
    }

    /// The contact of the boundary `name` of `mesh` with the face `face_name` of a deformable body
    /// in the same mesh (its nodes in the model's numbering). The gap of a head point is its
    /// distance in `x` to the face's polyline at its own height, continued past the face's ends
    /// where the energy fades out (see the module doc). The Hessian couples the head's edges with
    /// the face segments that they can touch turning about the pivot (the origin) while the bodies
    /// deform by less than `reach` \[m\] (see the module doc); the gradient is exact for all.
    #[allow(clippy::too_many_arguments)]
    pub fn deformable(
        mesh: &Mesh,
        name: &str,
        face_name: &str,
        stiffness: f64,
        thickness: f64,
        points_per_edge: usize,
        reach: f64,
    ) -> Result<Self, Error> {
        let mut nodes = mesh.nodes_on(face_name);
        if nodes.len() < 3 {
            return Err(Error::Mesh(format!(
                "the mesh has no boundary named \"{face_name}\" for the wall's contact face"
            )));
        }
        nodes.sort_by(|a, b| mesh.nodes[*a][1].total_cmp(&mesh.nodes[*b][1]));
        let face_x = mesh.nodes[nodes[0]][0];
        let mut wall = Self::new(mesh, name, face_x, stiffness, thickness, points_per_edge)?;
        let y = |k: usize| mesh.nodes[nodes[k]][1];
        let n = nodes.len();
        let taper = [y(1) - y(0), y(n - 1) - y(n - 2)];
        // the heights at which a head edge meets x = x_w turning about the pivot: y² = r² − x²,
        // r within `reach` of the edge's radii, x within `reach` of x_w
        let ax_lo = if face_x.abs() > reach {
            face_x.abs() - reach
        } else {
            0.0
        };
        let ax_hi = face_x.abs() + reach;
        let mut pairs = Vec::new();
        for (edge, e) in mesh.edges_named(name).enumerate() {
            let radii = e.nodes.map(|a| mesh.nodes[a][0].hypot(mesh.nodes[a][1]));
            let r_lo = (radii.iter().copied().fold(f64::INFINITY, f64::min) - reach).max(0.0);
            let r_hi = radii.iter().copied().fold(0.0, f64::max) + reach;
            let top2 = r_hi * r_hi - ax_lo * ax_lo;
            if top2 < 0.0 {
                continue;
            }
            let (b0, b1) = ((r_lo * r_lo - ax_hi * ax_hi).max(0.0).sqrt(), top2.sqrt());
            for j in 0..n - 1 {
                let lo = y(j) - reach - if j == 0 { taper[0] } else { 0.0 };
                let hi = y(j + 1) + reach + if j == n - 2 { taper[1] } else { 0.0 };
                if (lo <= b1 && hi >= b0) || (lo <= -b0 && hi >= -b1) {
                    pairs.push((edge, j));
                }
            }
        }
        wall.face = Some(Face {
            nodes,
            taper,
            pairs,
            reach,
        });
        Ok(wall)
    }

    /// The face segment `[j, j+1]` at height `y` of the current configuration: the end segment
    /// below or above the face.
    fn segment(&self, face: &Face, y: f64, u: &[f64]) -> usize {
        let yy = |k: usize| self.reference[face.nodes[k]][1] + u[2 * face.nodes[k] + 1];
        let n = face.nodes.len();
        // the face's heights stay in order (it deforms by micrometres)
        let (mut lo, mut hi) = (0, n - 1);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if yy(mid) <= y {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// The gap of point `p` at `u` and its gradient; with the face on the segment at the point's
    /// height, with its `η` (see the module doc).
    fn local(&self, p: &ContactPoint, u: &[f64]) -> Local {
        let mut l = self.local_behind(p, u);
        // deeper than the margin behind the face's line the point is behind the block, where
        // the face is no contact surface: no energy (η beyond the taper, fixed)
        if self.face.as_ref().is_some_and(|face| l.g < -face.reach) {
            l.eta = 2.0;
            l.deta = [0.0; 10];
        }
        l
    }

    /// As [`WallContact::local`], with the `η` of a point however far behind the face.
    fn local_behind(&self, p: &ContactPoint, u: &[f64]) -> Local {
        let ux: f64 = (0..3).map(|a| p.basis[a] * u[2 * p.nodes[a]]).sum();
        let mut l = Local {
            g: 0.0,
            eta: -1.0,
            dofs: [0; 10],
            grad: [0.0; 10],
            deta: [0.0; 10],
            n: 3,
            seg: 0,
        };
        for a in 0..3 {
            l.dofs[a] = 2 * p.nodes[a];
            l.grad[a] = p.basis[a];
        }
        let Some(face) = &self.face else {
            l.g = p.x_ref + ux - self.face_x;
            return l;
        };
        let xy = &self.reference;
        let y: f64 = (0..3)
            .map(|a| p.basis[a] * (xy[p.nodes[a]][1] + u[2 * p.nodes[a] + 1]))
            .sum();
        let j = self.segment(face, y, u);
        let (a, b) = (face.nodes[j], face.nodes[j + 1]);
        let (xa, ya) = (xy[a][0] + u[2 * a], xy[a][1] + u[2 * a + 1]);
        let (xb, yb) = (xy[b][0] + u[2 * b], xy[b][1] + u[2 * b + 1]);
        let dy = yb - ya;
        let slope = (xb - xa) / dy;
        let s = (y - ya) / dy;
        l.g = p.x_ref + ux - (xa + s * (xb - xa));
        for k in 0..3 {
            l.dofs[3 + k] = 2 * p.nodes[k] + 1;
            l.grad[3 + k] = -slope * p.basis[k];
        }
        l.dofs[6..10].copy_from_slice(&[2 * a, 2 * b, 2 * a + 1, 2 * b + 1]);
        l.grad[6..10].copy_from_slice(&[-(1.0 - s), -s, slope * (1.0 - s), slope * s]);
        l.n = 10;
        l.seg = j;
        // η from the nearer end: the lower node of a segment in the face's lower half, the upper
        // node in its upper half (exactly the end node on the end segments; ≤ 0 on the face)
        if 2 * j + 2 < face.nodes.len() {
            l.eta = (ya - y) / face.taper[0];
            for k in 0..3 {
                l.deta[3 + k] = -p.basis[k] / face.taper[0];
            }
            l.deta[8] = 1.0 / face.taper[0];
        } else {
            l.eta = (y - yb) / face.taper[1];
            for k in 0..3 {
                l.deta[3 + k] = p.basis[k] / face.taper[1];
            }
            l.deta[9] = -1.0 / face.taper[1];
        }
        l
    }

    /// The gap of `p` at `u` (`+∞` for a point beyond the taper past the face's ends).
    fn gap(&self, p: &ContactPoint, u: &[f64]) -> f64 {
        let l = self.local(p, u);
        if taper(l.eta) > 0.0 {
            l.g
        } else {
            f64::INFINITY
        }
    }

    fn density(&self, g: f64) -> f64 {
        let pen = g.min(0.0);
        0.5 * self.stiffness * pen * pen
    }

    /// The smallest gap over the contact points \[m\] (negative: the largest penetration). A
    /// point past the deformable face's end, in the taper (`0 < s(η) < 1`, the block's rounded
    /// corner), penetrates by `g √s(η)`: the penetration that stores its energy on the face. Its
    /// gap to the face's line continued beyond the block is no depth inside the block (there is
    /// no block there), and the energy does not bound it. The sign is the gap's.
    pub fn smallest_gap(&self, u: &[f64]) -> f64 {
        self.points
            .iter()
            .map(|p| {
                let l = self.local(p, u);
                match taper(l.eta) {
                    s if s <= 0.0 => f64::INFINITY,
                    s if l.g < 0.0 => l.g * s.sqrt(),
                    _ => l.g,
                }
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// The secant of each point's energy density along its gap (see the module doc), `ψ'(g)` when
    /// the ends coincide.
    fn secant(&self, g0: f64, g1: f64) -> f64 {
        let k = self.stiffness;
        if g0 <= 0.0 && g1 <= 0.0 {
            0.5 * k * (g0 + g1)
        } else if g0 >= 0.0 && g1 >= 0.0 {
            0.0
        } else {
            (self.density(g1) - self.density(g0)) / (g1 - g0)
        }
    }

    /// `∂ψ_d/∂g₁`, the derivative of the secant ([`WallContact::secant`]) with respect to the gap
    /// at the end of the step: `½ k` with both ends penetrating, 0 with both apart, and across the
    /// face `(ψ'(g₁) − ψ_d)/(g₁ − g₀)`, which is `k a (a + 2b) / (2 (a + b)²)` entering
    /// (`g₀ = b > 0`, `g₁ = −a`) and `k a² / (2 (a + b)²)` leaving (`g₀ = −a`, `g₁ = b`): never
    /// negative, and far from the `k` of the end-point Hessian when the point just crosses.
    fn secant_slope(&self, g0: f64, g1: f64) -> f64 {
        let k = self.stiffness;
        if g0 <= 0.0 && g1 <= 0.0 {
            0.5 * k
        } else if g0 >= 0.0 && g1 >= 0.0 {
            0.0
        } else {
            (k * g1.min(0.0) - self.secant(g0, g1)) / (g1 - g0)
        }
    }

    /// The resultant in `+x` of the wall's force over a step from `u0` to `u1` as the scheme applies
    /// it (the secant, or the end-point force with [`WallContact::end_point`]) \[N\]: its product with
    /// the step's length is the step's impulse.
    pub fn step_force(&self, u0: &[f64], u1: &[f64]) -> f64 {
        if self.end_point {
            return self.normal_force(u1);
        }
        self.points
            .iter()
            .map(|p| {
                let (l0, l1) = (self.local(p, u0), self.local(p, u1));
                -p.weight * 0.5 * (taper(l0.eta) + taper(l1.eta)) * self.secant(l0.g, l1.g)
            })
            .sum()
    }

    /// Whether any point penetrates the wall.
    pub fn in_contact(&self, u: &[f64]) -> bool {
        self.points.iter().any(|p| self.gap(p, u) < 0.0)
    }

    /// The first time `s ∈ (0, h]` at which a point now apart reaches the wall when the body
    /// turns rigidly about the pivot (the origin) by `φ(s) = ω s + ½ α s²`, if any.
    ///
    /// A point at distance `ρ` from the pivot and polar angle `β` moves on the circle
    /// `x(φ) = ρ cos(β + φ)`; the wall's face at the point, `x_f = x − g` with `g` its gap now (the
    /// plane `x = x_w` for the rigid wall), is reached at `β + φ = ± arccos(x_f/ρ)` (mod 2π), the
    /// first such turn in either sense, and the turn at time `s` is the smallest positive root of
    /// `½ α s² + ω s = φ`. Exact on the circle for any turn: the nodes' own quadratic flight
    /// `x + s v + ½ s² a` cuts the circle's chord and, over a step that turns the body by a
    /// radian, missed touches or placed them late (a plate spun to 90 rad/s then ended its step
    /// millimetres inside a stiff wall). The body's own deformation in the meantime is not
    /// foreseen; a step that ends inside the wall anyway is retaken up to the crossing
    /// ([`WallContact::first_crossing`]).
    pub fn first_touch(&self, u: &[f64], omega: f64, alpha: f64, h: f64) -> Option<f64> {
        use std::f64::consts::TAU;
        // the smallest s in (0, h] with ½ α s² + ω s = phi
        let time_of = |phi: f64| -> Option<f64> {
            let (a, b, c) = (0.5 * alpha, omega, -phi);
            let roots = if a == 0.0 {
                [(b != 0.0).then(|| -c / b), None]
            } else {
                let disc = b * b - 4.0 * a * c;
                if disc < 0.0 {
                    [None, None]
                } else {
                    let q = -0.5 * (b + b.signum() * disc.sqrt());
                    [(q != 0.0).then(|| q / a), (q != 0.0).then(|| c / q)]
                }
            };
            roots
                .into_iter()
                .flatten()
                .filter(|s| *s > 0.0 && *s <= h && s.is_finite())
                .reduce(f64::min)
        };
        let mut first: Option<f64> = None;
        for p in &self.points {
            let g0 = self.gap(p, u);
            if g0 <= 0.0 || !g0.is_finite() {
                continue;
            }
            let at = |k: usize| (0..3).map(|a| p.basis[a] * u[2 * p.nodes[a] + k]).sum::<f64>();
            let (x, y) = (p.x_ref + at(0), p.y_ref + at(1));
            let rho = x.hypot(y);
            let c = (x - g0) / rho;
            if !(-1.0..=1.0).contains(&c) {
                continue; // the face is out of the point's reach
            }
            let beta = y.atan2(x);
            let target = c.acos();
            for t in [target, -target] {
                // the turns that bring the point there, counter-clockwise and clockwise
                let ccw = (t - beta).rem_euclid(TAU);
                for phi in [ccw, ccw - TAU] {
                    if let Some(s) = time_of(phi) {
                        first = Some(first.map_or(s, |f: f64| f.min(s)));
                    }
                }
            }
        }
        first
    }

    /// The first fraction `s ∈ (0, 1]` of the straight path from `u0` (apart) to `u1` at which a
    /// point reaches the wall, if any (the gap is linear in `u`).
    pub fn first_crossing(&self, u0: &[f64], u1: &[f64]) -> Option<f64> {
        self.points
            .iter()
            .filter_map(|p| {
                let (g0, g1) = (self.gap(p, u0), self.gap(p, u1));
                (g0 > 0.0 && g1 < 0.0).then(|| g0 / (g0 - g1))
            })
            .reduce(f64::min)
    }

    /// The wall's force on the body, the resultant in `+x` \[N\].
    pub fn normal_force(&self, u: &[f64]) -> f64 {
        self.points
            .iter()
            .map(|p| {
                let l = self.local(p, u);
                // (−g)⁺, not −min(g, 0): a point apart adds +0, never −0
                p.weight * self.stiffness * (-l.g).max(0.0) * taper(l.eta)
            })
            .sum()
    }

    /// With the deformable face: a point of the head's arc that lies behind the face's line out
    /// of the face's reach at `u` (beyond its end, `η ≥ 1`, or deeper than the pattern's margin)
    /// and, with the head turned rigidly by `turn` \[rad\] about the pivot (the block stays),
    /// arrives where the face's energy acts deeper than a tenth of the margin behind it. Only the
    /// face is a contact surface: a point that enters its reach from behind, that deep, came round
    /// the face's end (a head that swung over the pivot comes down onto the block's top or
    /// back), where the face's energy sets in at that depth and its stiffness stops Newton. (A
    /// point pressed into the face that slides past its end and back is a few hundred µm deep.)
    /// Described for an error message.
    pub fn behind_face(&self, u: &[f64], turn: f64) -> Option<String> {
        let mut turned = u.to_vec();
        let arc = self.points.iter().flat_map(|p| p.nodes);
        crate::post::turn_about_pivot(&self.reference, u, &mut turned, arc, turn);
        self.arrival(u, &turned)
            .map(|what| format!("turning on by {turn:.4} rad, {what}"))
    }

    /// As [`WallContact::behind_face`] over a step taken, from `u0` to `u1`: a step that succeeds
    /// can carry the head round the face's end too, where the face's energy at its end pushed it
    /// back (seed 20's case 4 of the random-case campaign: the head swung over the pivot came
    /// down 16 mm behind the face's line beyond its end and bounced off the block's top corner,
    /// which the model does not have).
    pub fn came_round(&self, u0: &[f64], u1: &[f64]) -> Option<String> {
        self.arrival(u0, u1).map(|what| format!("over the step, {what}"))
    }

    /// The end of the sentence of [`WallContact::behind_face`] for the first point of the arc that
    /// comes round the face's end from `u0` to `u1`.
    fn arrival(&self, u0: &[f64], u1: &[f64]) -> Option<String> {
        let face = self.face.as_ref()?;
        self.points.iter().find_map(|p| {
            let l0 = self.local_behind(p, u0);
            let l = self.local_behind(p, u1);
            let behind = l0.g < 0.0 && (l0.eta >= 1.0 || l0.g < -face.reach);
            let arrives = behind && l.eta < 1.0 && (-face.reach..-0.1 * face.reach).contains(&l.g);
            arrives.then(|| {
                let y: f64 = (0..3)
                    .map(|a| p.basis[a] * (self.reference[p.nodes[a]][1] + u1[2 * p.nodes[a] + 1]))
                    .sum();
                format!(
                    "the head's arc arrives from beyond the deformable wall's face end at y = {y:.4} m, {:.4} m \
                     behind its line: it has come round the face's end (the face is the wall's only contact \
                     surface). Keep the head from going over the pivot (less initial speed or torque), or use \
                     wall.kind = \"rigid\", a half-plane it cannot pass",
                    -l.g
                )
            })
        })
    }

    /// A penetrating point whose head edge and face segment the Hessian pattern does not couple
    /// (the bodies deformed by more than the margin of [`WallContact::deformable`]), described for an
    /// error message; `None` when the pattern covers every contact (always for the rigid wall).
    pub fn uncoupled_contact(&self, u: &[f64]) -> Option<String> {
        let face = self.face.as_ref()?;
        self.points.iter().find_map(|p| {
            let l = self.local(p, u);
            let touching = l.g < 0.0 && taper(l.eta) > 0.0;
            (touching && face.pairs.binary_search(&(p.edge, l.seg)).is_err()).then(|| {
                let y: f64 = (0..3)
                    .map(|a| p.basis[a] * (self.reference[p.nodes[a]][1] + u[2 * p.nodes[a] + 1]))
                    .sum();
                format!(
                    "the head's contact edge {} touches the wall's face segment {} at y = {y:.6} m (penetration {:.3e} \
                     m), a pair the fixed sparsity pattern does not couple: the pattern holds the pairs that can touch \
                     while the bodies deform by less than {} m from a rigid turn about the pivot",
                    p.edge, l.seg, -l.g, face.reach
                )
            })
        })
    }

    /// The discrete gradient of one point's energy with the face (see the module doc), added times
    /// `f` into `g`.
    fn add_face_discrete_gradient(&self, p: &ContactPoint, u0: &[f64], u1: &[f64], mid: &[f64], f: f64, g: &mut [f64]) {
        let (l0, l1) = (self.local(p, u0), self.local(p, u1));
        if l0.g >= 0.0 && l1.g >= 0.0 {
            return;
        }
        let (a0, a1) = (self.density(l0.g), self.density(l1.g));
        let (b0, b1) = (taper(l0.eta), taper(l1.eta));
        let (psi_d, s_d) = (self.secant(l0.g, l1.g), taper_secant(l0.eta, l1.eta));
        let lm = self.local(p, mid);
        let du: Vec<f64> = (0..lm.n).map(|i| u1[lm.dofs[i]] - u0[lm.dofs[i]]).collect();
        let norm2: f64 = du.iter().map(|d| d * d).sum();
        // the mid-step gradients corrected along Δu: ∇ᵈg·Δu = g₁ − g₀, ∇ᵈη·Δu = η₁ − η₀
        let corrected = |grad: &[f64; 10], change: f64| -> [f64; 10] {
            let mut out = *grad;
            if norm2 > 0.0 {
                let lin: f64 = (0..lm.n).map(|i| grad[i] * du[i]).sum();
                let c = (change - lin) / norm2;
                for i in 0..lm.n {
                    out[i] += c * du[i];
                }
            }
            out
        };
        let dg = corrected(&lm.grad, l1.g - l0.g);
        let cg = f * p.weight * 0.5 * (b0 + b1) * psi_d;
        let ce = f * p.weight * 0.5 * (a0 + a1) * s_d;
        let deta = if ce != 0.0 {
            corrected(&lm.deta, l1.eta - l0.eta)
        } else {
            [0.0; 10]
        };
        for i in 0..lm.n {
            g[lm.dofs[i]] += cg * dg[i] + ce * deta[i];
        }
    }
}

impl Term for WallContact {
    fn name(&self) -> &'static str {
        "contact"
    }

    fn energy(&self, u: &[f64], _cx: &StepContext) -> f64 {
        self.points
            .iter()
            .map(|p| {
                let l = self.local(p, u);
                p.weight * self.density(l.g) * taper(l.eta)
            })
            .sum()
    }

    fn add_gradient(&self, u: &[f64], _cx: &StepContext, g: &mut [f64]) {
        for p in &self.points {
            let l = self.local(p, u);
            if l.g >= 0.0 {
                continue;
            }
            let s = taper(l.eta);
            let f = p.weight * self.stiffness * l.g * s;
            let fe = p.weight * self.density(l.g) * taper_slope(l.eta);
            for i in 0..l.n {
                g[l.dofs[i]] += f * l.grad[i] + fe * l.deta[i];
            }
        }
    }

    /// `k w s ∇g ∇gᵀ` of the penetrating points (for the deformable face without the gap's own
    /// curvature and the taper's derivatives: an approximate Jacobian, as Newton allows), into
    /// the pairs the pattern couples (see the module doc; a contact outside them is reported by
    /// [`WallContact::uncoupled_contact`], which the simulation checks after every step).
    fn add_hessian(&self, u: &[f64], _cx: &StepContext, pattern: &Pattern, values: &mut [f64]) {
        for p in &self.points {
            let l = self.local(p, u);
            let s = taper(l.eta);
            if l.g >= 0.0 || s == 0.0 {
                continue;
            }
            l.add_outer(p.weight * self.stiffness * s, pattern, values);
        }
    }

    /// The rigid wall: none (an edge's nodes share an element). The face: every pair of a head
    /// edge's and a face segment's degrees of freedom over the coupled pairs (see the module doc).
    fn hessian_entries(&self) -> Vec<(usize, usize)> {
        let Some(face) = &self.face else {
            return Vec::new();
        };
        let edges: Vec<[usize; 3]> = {
            let mut e: Vec<(usize, [usize; 3])> = self.points.iter().map(|p| (p.edge, p.nodes)).collect();
            e.dedup();
            e.into_iter().map(|(_, n)| n).collect()
        };
        let mut entries = Vec::new();
        for &(edge, j) in &face.pairs {
            let head = edges[edge].iter().flat_map(|&a| [2 * a, 2 * a + 1]);
            for r in head {
                for b in [face.nodes[j], face.nodes[j + 1]] {
                    for c in [2 * b, 2 * b + 1] {
                        entries.push((r.min(c), r.max(c)));
                    }
                }
            }
        }
        entries.sort_unstable();
        entries.dedup();
        entries
    }

    /// The Jacobian of the secant force over the step, `factor · w ∂ψ_d/∂g₁ ∇g ∇gᵀ` per point
    /// (`WallContact::secant_slope`; exact for the rigid wall, whose `g` is linear in `u`; for the
    /// deformable face with the taper and gradient at the end of the step). The Hessian
    /// at the end of the step, `k w ∇g ∇gᵀ` of the penetrating points, is wrong across the wall: a
    /// point that just enters gets `k` where the secant is nearly flat, a point that leaves gets 0
    /// where the secant still pushes; Newton then contracts by only `1 − ∂ψ_d/∂g₁ / k` per
    /// iteration, or oscillates between penetrating and apart (the stiff contacts of
    /// `tests/robustness.rs` did). The end-point force keeps the Hessian.
    fn add_discrete_hessian(
        &self,
        start: &StepStart,
        u1: &[f64],
        _cx: &StepContext,
        factor: f64,
        pattern: &Pattern,
        values: &mut [f64],
    ) -> bool {
        if self.end_point {
            return false;
        }
        for p in &self.points {
            let (l0, l1) = (self.local(p, start.u), self.local(p, u1));
            // the face: the taper at the end of the step, without its derivatives and the gap's
            // curvature (as in the Hessian); 1 for the rigid wall
            let slope = self.secant_slope(l0.g, l1.g) * taper(l1.eta);
            if slope == 0.0 {
                continue;
            }
            l1.add_outer(factor * p.weight * slope, pattern, values);
        }
        true
    }

    /// The secant of each point's energy along its gap (see the module doc).
    /// With [`WallContact::end_point`], the gradient at `u1` instead.
    fn add_discrete_gradient(
        &self,
        start: &StepStart,
        u1: &[f64],
        cx: &StepContext,
        factor: f64,
        g: &mut [f64],
    ) -> f64 {
        if self.face.is_some() && self.end_point {
            let mut own = vec![0.0; g.len()];
            self.add_gradient(u1, cx, &mut own);
            g.iter_mut().zip(&own).for_each(|(a, b)| *a += factor * b);
            return self.energy(u1, cx);
        }
        if self.face.is_some() {
            let mid: Vec<f64> = start.u.iter().zip(u1).map(|(a, b)| 0.5 * (a + b)).collect();
            for p in &self.points {
                self.add_face_discrete_gradient(p, start.u, u1, &mid, factor, g);
            }
            return self.energy(u1, cx);
        }
        for p in &self.points {
            let (l0, l1) = (self.local(p, start.u), self.local(p, u1));
            let secant = if self.end_point {
                self.stiffness * l1.g.min(0.0)
            } else {
                self.secant(l0.g, l1.g)
            };
            if secant == 0.0 {
                continue;
            }
            let f = factor * p.weight * secant;
            for i in 0..l1.n {
                g[l1.dofs[i]] += f * l1.grad[i];
            }
        }
        self.energy(u1, cx)
    }
}
