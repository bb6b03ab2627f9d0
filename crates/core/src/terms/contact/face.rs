//! The deformable wall's face: the polyline through the block's face nodes, its constructor with
//! the head edge and face segment pairs the Hessian pattern couples, the discrete gradient with
//! the taper, and the checks for a head that came round the face's end or an uncoupled contact.

use super::law::{taper, taper_secant};
use super::points::ContactPoint;
use super::WallContact;
use crate::error::Error;
use crate::mesh::Mesh;

/// The deformable wall's face: the nodes of its contact edge, sorted by reference `y`, as a
/// polyline (straight pieces between consecutive nodes).
#[derive(Clone, Debug)]
pub(super) struct Face {
    pub(super) nodes: Vec<usize>,
    /// Taper lengths `ℓ` past the bottom and the top end: the end segments' reference lengths \[m\].
    pub(super) taper: [f64; 2],
    /// The `(head edge, face segment)` pairs that the Hessian pattern couples, sorted.
    pub(super) pairs: Vec<(usize, usize)>,
    /// The deformation margin of the pairs \[m\].
    pub(super) reach: f64,
}

impl WallContact {
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
        crate::rigid::turn_about_pivot(&self.reference, u, &mut turned, arc, turn);
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
    pub(super) fn add_face_discrete_gradient(
        &self,
        p: &ContactPoint,
        u0: &[f64],
        u1: &[f64],
        mid: &[f64],
        f: f64,
        g: &mut [f64],
    ) {
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
