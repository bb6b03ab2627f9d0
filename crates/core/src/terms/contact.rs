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
    /// The quadratic edge basis at the point.
    basis: [f64; 3],
    /// Reference `x` of the point \[m\].
    x_ref: f64,
    /// Reference arc length times thickness \[m²\].
    weight: f64,
}

/// The deformable wall's face: the nodes of its contact edge, sorted by reference `y`, as a
/// polyline (straight pieces between consecutive nodes).
#[derive(Clone, Debug)]
struct Face {
    nodes: Vec<usize>,
}

/// A point's gap and its gradient over its local degrees of freedom.
struct Local {
    g: f64,
    dofs: [usize; 10],
    grad: [f64; 10],
    n: usize,
}

/// The wall `x ≤ x_w` against the named boundary (see the module doc); rigid, or with the face of
/// a deformable body ([`RigidWall::deformable`]).
#[derive(Clone, Debug)]
pub struct RigidWall {
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
    /// Degrees of freedom whose couplings the Hessian writes (see [`Term::hessian_entries`]).
    coupled: Vec<usize>,
    /// Reference coordinates of the mesh's nodes \[m\].
    reference: Vec<[f64; 2]>,
}

impl RigidWall {
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
        for e in mesh.edges_named(name) {
            let x = e.nodes.map(|n| mesh.nodes[n]);
            for &(s, w) in &rule {
                let n = Tri6::edge_basis(s);
                let dn = Tri6::edge_basis_derivatives(s);
                let dx = [0, 1].map(|i| (0..3).map(|a| dn[a] * x[a][i]).sum::<f64>());
                points.push(ContactPoint {
                    nodes: e.nodes,
                    basis: n,
                    x_ref: (0..3).map(|a| n[a] * x[a][0]).sum(),
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
            coupled: Vec::new(),
            reference: mesh.nodes.clone(),
        })
    }

    /// The contact of the boundary `name` of `mesh` with the face `face_name` of a deformable body
    /// in the same mesh (its nodes in the model's numbering). The gap of a head point is its
    /// distance in `x` to the face's polyline at its own height (the face is the vertical edge of
    /// the block; points above or below it are apart). The Hessian couples the `x` components of
    /// the head's nodes within `reach` of its leftmost point and of the face's nodes within `reach`
    /// of their heights: the Jacobian of the pairs that can touch; the gradient is exact for all.
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
        if nodes.len() < 2 {
            return Err(Error::Mesh(format!(
                "the mesh has no boundary named \"{face_name}\" for the wall's contact face"
            )));
        }
        nodes.sort_by(|a, b| mesh.nodes[*a][1].total_cmp(&mesh.nodes[*b][1]));
        let face_x = mesh.nodes[nodes[0]][0];
        let mut wall = Self::new(mesh, name, face_x, stiffness, thickness, points_per_edge)?;
        let head = mesh.nodes_on(name);
        let left = head.iter().map(|&n| mesh.nodes[n][0]).fold(f64::INFINITY, f64::min);
        let near: Vec<usize> = head.into_iter().filter(|&n| mesh.nodes[n][0] < left + reach).collect();
        let (lo, hi) = near.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &n| {
            (lo.min(mesh.nodes[n][1]), hi.max(mesh.nodes[n][1]))
        });
        let facing = nodes
            .iter()
            .copied()
            .filter(|&n| (lo - reach..=hi + reach).contains(&mesh.nodes[n][1]));
        wall.coupled = near.iter().copied().chain(facing).map(|n| 2 * n).collect();
        wall.coupled.sort_unstable();
        wall.face = Some(Face { nodes });
        Ok(wall)
    }

    /// The face segment `[j, j+1]` at height `y` of the current configuration, if within the face.
    fn segment(&self, face: &Face, y: f64, u: &[f64], mesh_nodes: &[[f64; 2]]) -> Option<usize> {
        let yy = |k: usize| mesh_nodes[face.nodes[k]][1] + u[2 * face.nodes[k] + 1];
        let n = face.nodes.len();
        if y < yy(0) || y > yy(n - 1) {
            return None;
        }
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
        Some(lo)
    }

    /// The gap of point `p` at `u` and its gradient; `seg`: the face segment to use (`None`: the
    /// one at the point's height). `None` when the point is above or below the face.
    fn local(&self, p: &ContactPoint, u: &[f64], seg: Option<usize>) -> Option<Local> {
        let ux: f64 = (0..3).map(|a| p.basis[a] * u[2 * p.nodes[a]]).sum();
        let mut l = Local {
            g: 0.0,
            dofs: [0; 10],
            grad: [0.0; 10],
            n: 3,
        };
        for a in 0..3 {
            l.dofs[a] = 2 * p.nodes[a];
            l.grad[a] = p.basis[a];
        }
        let Some(face) = &self.face else {
            l.g = p.x_ref + ux - self.face_x;
            return Some(l);
        };
        let xy = &self.reference;
        let y: f64 = (0..3)
            .map(|a| p.basis[a] * (xy[p.nodes[a]][1] + u[2 * p.nodes[a] + 1]))
            .sum();
        let j = match seg {
            Some(j) => j,
            None => self.segment(face, y, u, xy)?,
        };
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
        Some(l)
    }

    fn gap(&self, p: &ContactPoint, u: &[f64]) -> f64 {
        self.local(p, u, None).map_or(f64::INFINITY, |l| l.g)
    }

    fn density(&self, g: f64) -> f64 {
        let pen = g.min(0.0);
        0.5 * self.stiffness * pen * pen
    }

    /// The smallest gap over the contact points \[m\] (negative: the largest penetration).
    pub fn smallest_gap(&self, u: &[f64]) -> f64 {
        self.points.iter().map(|p| self.gap(p, u)).fold(f64::INFINITY, f64::min)
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

    /// `∂ψ_d/∂g₁`, the derivative of the secant ([`RigidWall::secant`]) with respect to the gap
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

    /// The face segment a point uses over a step (`Some(None)` for the rigid wall): the one at the
    /// point's mid-step height, the same for both ends so that the secant is exact for the gap it
    /// uses; `None` when the point is above or below the face at mid-step.
    fn step_segment(&self, p: &ContactPoint, mid: &[f64]) -> Option<Option<usize>> {
        let Some(face) = &self.face else {
            return Some(None);
        };
        let y: f64 = (0..3)
            .map(|a| p.basis[a] * (self.reference[p.nodes[a]][1] + mid[2 * p.nodes[a] + 1]))
            .sum();
        self.segment(face, y, mid, &self.reference).map(Some)
    }

    /// The resultant in `+x` of the wall's force over a step from `u0` to `u1` as the scheme applies
    /// it (the secant, or the end-point force with [`RigidWall::end_point`]) \[N\]: its product with
    /// the step's length is the step's impulse.
    pub fn step_force(&self, u0: &[f64], u1: &[f64]) -> f64 {
        if self.end_point {
            return self.normal_force(u1);
        }
        self.points
            .iter()
            .map(|p| -p.weight * self.secant(self.gap(p, u0), self.gap(p, u1)))
            .sum()
    }

    /// Whether any point penetrates the wall.
    pub fn in_contact(&self, u: &[f64]) -> bool {
        self.points.iter().any(|p| self.gap(p, u) < 0.0)
    }

    /// The first time `s ∈ (0, h]` at which a point now apart reaches the wall along the free
    /// flight `x(s) = x + s v + ½ s² a` of every point (the gap is quadratic in `s`), if any.
    pub fn first_touch(&self, u: &[f64], v: &[f64], a: &[f64], h: f64) -> Option<f64> {
        let mut first: Option<f64> = None;
        for p in &self.points {
            let g0 = self.gap(p, u);
            if g0 <= 0.0 {
                continue;
            }
            let at = |f: &[f64]| (0..3).map(|k| p.basis[k] * f[2 * p.nodes[k]]).sum::<f64>();
            let (g1, g2) = (at(v), 0.5 * at(a));
            // smallest positive root of g0 + g1 s + g2 s² (g0 > 0)
            let root = if g2 == 0.0 {
                (g1 < 0.0).then(|| -g0 / g1)
            } else {
                let disc = g1 * g1 - 4.0 * g2 * g0;
                (disc >= 0.0)
                    .then(|| {
                        let q = -0.5 * (g1 + g1.signum() * disc.sqrt());
                        [q / g2, g0 / q]
                    })
                    .and_then(|r| r.into_iter().filter(|s| *s > 0.0 && s.is_finite()).reduce(f64::min))
            };
            if let Some(s) = root.filter(|s| *s <= h) {
                first = Some(first.map_or(s, |f: f64| f.min(s)));
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
            .map(|p| -p.weight * self.stiffness * self.gap(p, u).min(0.0))
            .sum()
    }
}

impl Term for RigidWall {
    fn name(&self) -> &'static str {
        "contact"
    }

    fn energy(&self, u: &[f64], _cx: &StepContext) -> f64 {
        self.points
            .iter()
            .map(|p| p.weight * self.density(self.gap(p, u)))
            .sum()
    }

    fn add_gradient(&self, u: &[f64], _cx: &StepContext, g: &mut [f64]) {
        for p in &self.points {
            let Some(l) = self.local(p, u, None) else {
                continue;
            };
            let f = p.weight * self.stiffness * l.g.min(0.0);
            for i in 0..l.n {
                g[l.dofs[i]] += f * l.grad[i];
            }
        }
    }

    /// `k w ∇g ∇gᵀ` of the penetrating points (for the deformable face without the gap's own
    /// curvature, and only in the coupled entries: an approximate Jacobian, as Newton allows).
    fn add_hessian(&self, u: &[f64], _cx: &StepContext, pattern: &Pattern, values: &mut [f64]) {
        for p in &self.points {
            let Some(l) = self.local(p, u, None).filter(|l| l.g < 0.0) else {
                continue;
            };
            let c = p.weight * self.stiffness;
            for i in 0..l.n {
                for j in 0..l.n {
                    let (r, col) = (l.dofs[i], l.dofs[j]);
                    if r > col {
                        continue;
                    }
                    match pattern.position(r, col) {
                        Some(pos) => values[pos] += c * l.grad[i] * l.grad[j],
                        None => debug_assert!(self.face.is_some(), "the nodes of an edge share an element"),
                    }
                }
            }
        }
    }

    fn hessian_entries(&self) -> Vec<(usize, usize)> {
        super::dense_block(&self.coupled)
    }

    /// The Jacobian of the secant force over the step: `factor · w ∂ψ_d/∂g₁ ∇g ∇gᵀ` per point
    /// ([`RigidWall::secant_slope`]; for the deformable face with the gap's gradient at the end of
    /// the step, without the gap's own curvature). The Hessian at the end of the step, `k w ∇g ∇gᵀ`
    /// of the penetrating points, is twice too stiff while both ends penetrate (`factor` = 2 puts
    /// that right) and wrong across the face: a point that just enters gets `k` where the secant
    /// is nearly flat, a point that leaves gets 0 where the secant still pushes; Newton then
    /// contracts by only `1 − ∂ψ_d/∂g₁ / k` per iteration, or oscillates between penetrating and
    /// apart.
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
        let mid: Vec<f64> = match self.face {
            Some(_) => start.u.iter().zip(u1).map(|(a, b)| 0.5 * (a + b)).collect(),
            None => Vec::new(),
        };
        for p in &self.points {
            let Some(seg) = self.step_segment(p, &mid) else {
                continue;
            };
            let (Some(l0), Some(l1)) = (self.local(p, start.u, seg), self.local(p, u1, seg)) else {
                continue;
            };
            let slope = self.secant_slope(l0.g, l1.g);
            if slope == 0.0 {
                continue;
            }
            let c = factor * p.weight * slope;
            for i in 0..l1.n {
                for j in 0..l1.n {
                    let (r, col) = (l1.dofs[i], l1.dofs[j]);
                    if r > col {
                        continue;
                    }
                    match pattern.position(r, col) {
                        Some(pos) => values[pos] += c * l1.grad[i] * l1.grad[j],
                        None => debug_assert!(self.face.is_some(), "the nodes of an edge share an element"),
                    }
                }
            }
        }
        true
    }

    /// The secant of each point's energy along its gap (see the module doc).
    /// With [`RigidWall::end_point`], the gradient at `u1` instead.
    fn add_discrete_gradient(
        &self,
        start: &StepStart,
        u1: &[f64],
        cx: &StepContext,
        factor: f64,
        g: &mut [f64],
    ) -> f64 {
        let mid: Vec<f64> = match self.face {
            Some(_) => start.u.iter().zip(u1).map(|(a, b)| 0.5 * (a + b)).collect(),
            None => Vec::new(),
        };
        for p in &self.points {
            let Some(seg) = self.step_segment(p, &mid) else {
                continue;
            };
            let (Some(l0), Some(l1)) = (self.local(p, start.u, seg), self.local(p, u1, seg)) else {
                continue;
            };
            let secant = if self.end_point {
                self.stiffness * l1.g.min(0.0)
            } else {
                self.secant(l0.g, l1.g)
            };
            if secant == 0.0 {
                continue;
            }
            let f = factor * p.weight * secant;
            let mut grad = l1.grad;
            if self.face.is_some() && !self.end_point {
                // a discrete gradient of the gap (it is nonlinear in u for the deformable face):
                // the mid-step gradient corrected along Δu so that ∇ᵈg·Δu = g₁ − g₀ exactly
                let lm = self.local(p, &mid, seg).expect("the segment exists at mid-step");
                let du: Vec<f64> = (0..l1.n).map(|i| u1[l1.dofs[i]] - start.u[l1.dofs[i]]).collect();
                let lin: f64 = (0..l1.n).map(|i| lm.grad[i] * du[i]).sum();
                let norm2: f64 = du.iter().map(|d| d * d).sum();
                grad = lm.grad;
                if norm2 > 0.0 {
                    let c = (l1.g - l0.g - lin) / norm2;
                    for i in 0..l1.n {
                        grad[i] += c * du[i];
                    }
                }
            }
            for i in 0..l1.n {
                g[l1.dofs[i]] += f * grad[i];
            }
        }
        self.energy(u1, cx)
    }
}
