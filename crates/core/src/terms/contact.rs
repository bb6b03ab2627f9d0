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

mod face;
mod gap;
mod law;
mod points;
mod touch;

use super::{StepContext, StepStart, Term};
use crate::assembly::Pattern;
use face::Face;
use law::{taper, taper_slope};
use points::ContactPoint;

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
