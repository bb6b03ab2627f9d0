//! What a reduced body reports, from its coordinates alone (no field of the full model):
//!
//! * the proxy angle of the full model ([`crate::post::RigidProjection`]): with
//!   `x = R(θ)(X + Φq)`, `∫ X̄ x = e^{iθ} (P + c·q + i s·q)` (complex notation, `P = ∫|X|² dA`,
//!   `c_k`, `s_k` the projection's functionals of mode `k`), so `θ_proxy = θ + atan2(s·q, P + c·q)`;
//! * the best-fit rates as the full model defines them: `ω = L / I(q)` (`L = p_θ`) and
//!   `α = (moment of gravity, torque and wall about the pivot) / I(q)`;
//! * the stresses by modal superposition: the stress at every element node is linear in the
//!   modes, `σ = Σ q_k σ_k` (`σ_k` the small-strain stress of mode `k`, in the frame), its von Mises
//!   value averaged at the nodes as the full model does ([`crate::post::StressRecovery`]); von
//!   Mises does not depend on the frame's rotation. A linear stress: small strains, as the modes.
//! * the wall's smallest gap and normal force at the arc's quadrature points.

use super::{rotate, ReducedBody, ReducedState};
use crate::material::von_mises;
use crate::post::NodalStress;
use crate::terms::WallContact;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The modes' stresses at the element nodes and how they average at the nodes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StressModes {
    /// `σ_k` per element node and component (`[σxx, σyy, σxy, σzz]`), mode by mode: index
    /// `k · 4 N + e · 4 + c` (`N` element nodes) \[Pa per unit amplitude\].
    pub values: Vec<f64>,
    /// The mesh node of each element node.
    pub nodes: Vec<usize>,
    /// Elements per mesh node.
    pub counts: Vec<f64>,
}

/// The proxy angle's functionals of the modes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProxyModes {
    /// `P = ∫ |X|² dA` \[m⁴\].
    pub polar: f64,
    /// `c_k = ∫ X·φ_k dA`.
    pub cos: Vec<f64>,
    /// `s_k = ∫ X × φ_k dA`.
    pub sin: Vec<f64>,
}

impl ReducedBody {
    /// The full model's proxy angle of a state \[rad\], on the branch of `θ`.
    pub fn proxy_angle(&self, s: &ReducedState) -> f64 {
        let p = &self.proxy;
        s.theta + dot(&p.sin, &s.q).atan2(p.polar + dot(&p.cos, &s.q))
    }

    /// `(ω, α)` as the full model's best fit defines them (see the module doc), for gravity `g`,
    /// the torque `torque` and the wall, if any.
    pub fn rates(&self, s: &ReducedState, g: f64, torque: f64, wall: Option<&WallContact>) -> (f64, f64) {
        let inertia = self.inertia_at(&s.q);
        let m = self.first_moment(&s.q);
        let (sn, cs) = s.theta.sin_cos();
        // −∂V_g/∂θ = −g (cos θ m_x − sin θ m_y)
        let mut moment = -g * (cs * m[0] - sn * m[1]) + torque;
        if let Some(wall) = wall {
            for pt in &self.arc {
                let gap = self.gap(pt, s.theta, &s.q, wall.face_x);
                if gap < 0.0 {
                    let y = pt.in_frame(&s.q);
                    let x = rotate(s.theta, y);
                    // the force k (−g) w e_x at x: its moment x × f = −x_y f_x
                    moment -= x[1] * pt.weight * wall.stiffness * -gap;
                }
            }
        }
        (self.momenta(s)[0] / inertia, moment / inertia)
    }

    /// Contact energy \[J\], smallest gap \[m\] and the wall's normal force \[N\] of a state.
    pub fn contact(&self, s: &ReducedState, wall: &WallContact) -> (f64, f64, f64) {
        let (mut energy, mut smallest, mut force) = (0.0, f64::INFINITY, 0.0);
        for pt in &self.arc {
            let gap = self.gap(pt, s.theta, &s.q, wall.face_x);
            smallest = smallest.min(gap);
            if gap < 0.0 {
                energy += pt.weight * 0.5 * wall.stiffness * gap * gap;
                force += pt.weight * wall.stiffness * -gap;
            }
        }
        (energy, smallest, force)
    }

    /// The element-node stresses of a state, in the frame, into `out` (4 per element node).
    fn element_stresses(&self, q: &[f64], out: &mut Vec<[f64; 4]>) {
        let sm = &self.stress;
        let len = 4 * sm.nodes.len();
        out.clear();
        out.resize(sm.nodes.len(), [0.0; 4]);
        let flat = out.as_flattened_mut();
        // mode by mode, an axpy over every element node's components (contiguous: it vectorises)
        for (k, &a) in q.iter().enumerate() {
            if a != 0.0 {
                let col = &sm.values[k * len..(k + 1) * len];
                flat.iter_mut().zip(col).for_each(|(y, x)| *y += a * x);
            }
        }
    }

    /// The largest nodal von Mises stress of a state \[Pa\] (see the module doc).
    pub fn von_mises_max(&self, s: &ReducedState) -> f64 {
        self.nodal_stress(s).max_von_mises
    }

    /// The averaged nodal Cauchy stress (global axes) and von Mises stress of a state \[Pa\].
    pub fn nodal_stress(&self, s: &ReducedState) -> NodalStress {
        let sm = &self.stress;
        let nn = sm.counts.len();
        let mut out = NodalStress {
            cauchy: vec![[0.0; 3]; nn],
            von_mises: vec![0.0; nn],
            max_von_mises: 0.0,
        };
        let mut values = Vec::new();
        self.element_stresses(&s.q, &mut values);
        for (&node, v) in sm.nodes.iter().zip(&values) {
            for i in 0..3 {
                out.cauchy[node][i] += v[i];
            }
            out.von_mises[node] += von_mises([v[0], v[1], v[2]], v[3]);
        }
        let (sn, cs) = s.theta.sin_cos();
        for (n, c) in sm.counts.iter().enumerate().filter(|(_, c)| **c > 0.0) {
            let [a, b, d] = out.cauchy[n].map(|x| x / c);
            // σ_global = R σ Rᵀ
            out.cauchy[n] = [
                cs * cs * a - 2.0 * sn * cs * d + sn * sn * b,
                sn * sn * a + 2.0 * sn * cs * d + cs * cs * b,
                sn * cs * (a - b) + (cs * cs - sn * sn) * d,
            ];
            out.von_mises[n] /= c;
        }
        out.max_von_mises = out.von_mises.iter().copied().fold(0.0, f64::max);
        out
    }
}
