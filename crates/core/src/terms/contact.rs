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

/// The rigid wall `x ≤ x_w` against the named boundary (see the module doc).
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
        })
    }

    fn gap(&self, p: &ContactPoint, u: &[f64]) -> f64 {
        let ux: f64 = (0..3).map(|a| p.basis[a] * u[2 * p.nodes[a]]).sum();
        p.x_ref + ux - self.face_x
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
            let f = p.weight * self.stiffness * self.gap(p, u).min(0.0);
            for a in 0..3 {
                g[2 * p.nodes[a]] += f * p.basis[a];
            }
        }
    }

    fn add_hessian(&self, u: &[f64], _cx: &StepContext, pattern: &Pattern, values: &mut [f64]) {
        for p in &self.points {
            let active = if self.gap(p, u) < 0.0 { 1.0 } else { 0.0 };
            let c = active * p.weight * self.stiffness;
            for a in 0..3 {
                for b in 0..3 {
                    let (r, col) = (2 * p.nodes[a], 2 * p.nodes[b]);
                    if r <= col {
                        let pos = pattern.position(r, col).expect("the nodes of an edge share an element");
                        values[pos] += c * p.basis[a] * p.basis[b];
                    }
                }
            }
        }
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
        for p in &self.points {
            let (g0, g1) = (self.gap(p, start.u), self.gap(p, u1));
            let secant = if self.end_point {
                self.stiffness * g1.min(0.0)
            } else {
                self.secant(g0, g1)
            };
            let f = factor * p.weight * secant;
            for a in 0..3 {
                g[2 * p.nodes[a]] += f * p.basis[a];
            }
        }
        self.energy(u1, cx)
    }
}
