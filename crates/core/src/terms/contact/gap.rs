//! A point's gap and its gradient over its local degrees of freedom: to the rigid half-plane
//! `x ≤ x_w`, or to the deformable face's segment at the point's height with the point's `η`
//! past the face's nearer end.

use super::face::Face;
use super::law::taper;
use super::points::ContactPoint;
use super::WallContact;
use crate::assembly::Pattern;

/// A point's gap and its gradient over its local degrees of freedom; with the face also its
/// height past the face's nearer end in taper lengths and the gradient of that.
pub(super) struct Local {
    pub(super) g: f64,
    /// `η` (≤ 0 on the face; −1 for the rigid wall).
    pub(super) eta: f64,
    pub(super) dofs: [usize; 10],
    pub(super) grad: [f64; 10],
    pub(super) deta: [f64; 10],
    pub(super) n: usize,
    /// The face segment used.
    pub(super) seg: usize,
}

impl Local {
    /// `values += c ∇g ∇gᵀ` in the upper triangle of `pattern`. Pairs outside the pattern occur
    /// only on the deformable face (beyond its coupled pairs), where
    /// [`WallContact::uncoupled_contact`] stops the step after it; they are skipped.
    pub(super) fn add_outer(&self, c: f64, pattern: &Pattern, values: &mut [f64]) {
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

impl WallContact {
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
    pub(super) fn local(&self, p: &ContactPoint, u: &[f64]) -> Local {
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
    pub(super) fn local_behind(&self, p: &ContactPoint, u: &[f64]) -> Local {
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
    pub(super) fn gap(&self, p: &ContactPoint, u: &[f64]) -> f64 {
        let l = self.local(p, u);
        if taper(l.eta) > 0.0 {
            l.g
        } else {
            f64::INFINITY
        }
    }
}
