//! What a reduced body reports, from its coordinates alone (no field of the full model):
//!
//! * the proxy angle of the full model ([`crate::rigid::RigidProjection`]): with
//!   `x = R(θ)(X + Φq)`, `∫ X̄ x = e^{iθ} (P + c·q + i s·q)` (complex notation, `P = ∫|X|² dA`,
//!   `c_k`, `s_k` the projection's functionals of mode `k`), so `θ_proxy = θ + atan2(s·q, P + c·q)`;
//! * the best-fit rates as the full model defines them: `ω = L / I(q)` (`L = p_θ`) and
//!   `α = (moment of gravity, torque and wall about the pivot) / I(q)`;
//! * the stresses by modal superposition: the stress at every element node is linear in the
//!   modes, `σ = Σ q_k σ_k` (`σ_k` the small-strain stress of mode `k`, in the frame), its von Mises
//!   value averaged at the nodes as the full model does ([`crate::post::StressRecovery`]); von
//!   Mises does not depend on the frame's rotation. A linear stress: small strains, as the modes.
//! * the wall's smallest gap and normal force at the arc's quadrature points.

use rayon::prelude::*;

use super::{rotate, ReducedBody, ReducedState};
use crate::material::von_mises;
use crate::modal::constrained::dot;
use crate::post::NodalStress;
use crate::terms::WallContact;

/// The modes' stresses at the element nodes and how they average at the nodes.
#[derive(Clone, Debug, Default)]
pub struct StressModes {
    /// `σ_k` per element node and component (`[σxx, σyy, σxy, σzz]`), mode by mode: index
    /// `k · 4 N + e · 4 + c` (`N` element nodes) \[Pa per unit amplitude\].
    pub values: Vec<f64>,
    /// The mesh node of each element node.
    pub nodes: Vec<usize>,
    /// Elements per mesh node.
    pub counts: Vec<f64>,
    /// The element nodes of each mesh node and the modes' bounds, made on the first
    /// [`ReducedBody::von_mises_max`].
    pub index: std::sync::OnceLock<NodeBounds>,
}

/// The element nodes of each mesh node (ascending, as [`ReducedBody::nodal_stress`] sums them)
/// and, mode by mode, the averaged von Mises stress of the mode alone at each node,
/// `B_k(n) = (1/c_n) Σ_{e∋n} vM(σ_k(e, n))`.
///
/// Von Mises is a seminorm of the stress (the square root of a positive semidefinite quadratic
/// form), and the stress at an element node is linear in the amplitudes. So with the nodal values
/// `V(n, q̂)` of any state `q̂`, at every node `V(n, q) ≤ V(n, q̂) + Σ_k |q_k − q̂_k| B_k(n)`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeBounds {
    /// `members[starts[n]..starts[n + 1]]`: the element nodes of mesh node `n`.
    starts: Vec<usize>,
    members: Vec<usize>,
    /// The number of modes `K`.
    modes: usize,
    /// `B_k(n)` node after node, at index `n · K + k` \[Pa per unit amplitude\].
    by_node: Vec<f64>,
    /// `max_n B_k(n)` of each mode.
    mode_max: Vec<f64>,
}

impl NodeBounds {
    /// `Σ_k w_k B_k(n)`, the modes in order.
    fn weighted(&self, n: usize, weights: &[f64]) -> f64 {
        let b = &self.by_node[n * self.modes..(n + 1) * self.modes];
        weights.iter().zip(b).map(|(w, b)| w * b).sum()
    }
}

/// A state `q̂` with its nodal values `V(n, q̂)` and `T(n, q̂) = Σ_k |q̂_k| B_k(n)` (the scale of
/// their rounding): the last state whose every nodal value [`ReducedBody::von_mises_max`]
/// evaluated, kept by the simulation between calls. Any state serves (the bounds hold for every
/// `q̂`); a close one makes them tight.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StressReference(Option<Reference>);

#[derive(Clone, Debug, PartialEq)]
struct Reference {
    q: Vec<f64>,
    /// `V(n, q̂) + BOUND_MARGIN T(n, q̂)` of every node.
    base: Vec<f64>,
    /// The nodes of the body by `base`, largest first.
    order: Vec<u32>,
}

/// Relative margin on the bounds of [`NodeBounds`], of `T(n, q) + T(n, q̂)`, against the rounding
/// of the sums that evaluate the nodal values (`~1e-15` of `T` each).
const BOUND_MARGIN: f64 = 1e-9;

/// The share of the nodes above which [`ReducedBody::von_mises_max`] evaluates every node and
/// takes the state as its new reference, rather than evaluating the candidates one by one.
const CANDIDATE_SHARE: usize = 16;

impl PartialEq for StressModes {
    /// The same modes (the index is made from them).
    fn eq(&self, other: &Self) -> bool {
        (&self.values, &self.nodes, &self.counts) == (&other.values, &other.nodes, &other.counts)
    }
}

impl StressModes {
    /// Makes the index of [`ReducedBody::von_mises_max`] now rather than at its first call (a
    /// set-up does it beside its other work).
    pub fn prepare(&self) {
        self.node_bounds();
    }

    /// The element nodes per mesh node and the modes' nodal bounds (see [`NodeBounds`]).
    fn node_bounds(&self) -> &NodeBounds {
        self.index.get_or_init(|| {
            let nn = self.counts.len();
            let mut starts = vec![0usize; nn + 1];
            for &n in &self.nodes {
                starts[n + 1] += 1;
            }
            for n in 0..nn {
                starts[n + 1] += starts[n];
            }
            let mut fill = starts.clone();
            let mut members = vec![0; self.nodes.len()];
            for (en, &n) in self.nodes.iter().enumerate() {
                members[fill[n]] = en;
                fill[n] += 1;
            }
            let len = 4 * self.nodes.len();
            let modes = self.values.len().checked_div(len).unwrap_or(0);
            let mut bounds = vec![0.0; modes * nn];
            // mode by mode on the pool's threads
            bounds.par_chunks_mut(nn.max(1)).enumerate().for_each(|(k, b)| {
                let col = &self.values[k * len..(k + 1) * len];
                for (en, &n) in self.nodes.iter().enumerate() {
                    let v = &col[4 * en..4 * en + 4];
                    b[n] += von_mises([v[0], v[1], v[2]], v[3]);
                }
                for (bn, c) in b.iter_mut().zip(&self.counts) {
                    if *c > 0.0 {
                        *bn /= c;
                    }
                }
            });
            let by_node = (0..nn * modes).map(|i| bounds[(i % modes) * nn + i / modes]).collect();
            let mode_max = bounds
                .chunks(nn.max(1))
                .map(|b| b.iter().fold(0.0, |a: f64, x| a.max(*x)))
                .collect();
            NodeBounds {
                starts,
                members,
                modes,
                by_node,
                mode_max,
            }
        })
    }

    /// The largest nodal value at `q` from the reference `r`, exact: the nodes in the order of
    /// `V(n, q̂)` (with its margin), each one's bound
    /// `V(n, q̂) + Σ_k w_k B_k(n)` with `w_k = |q_k − q̂_k| + BOUND_MARGIN |q_k|` (the margin of
    /// `T(n, q̂) + T(n, q)`), and its exact value where the bound reaches the largest value found
    /// so far. The walk stops where even `V(n, q̂) + Σ_k w_k max_n B_k` falls short of it: no later
    /// node can reach it, the largest node's value among them included. `None` when more than a
    /// [`CANDIDATE_SHARE`]th of the nodes would be evaluated (the state is far from `q̂`).
    fn bounded_max(&self, index: &NodeBounds, q: &[f64], r: &Reference) -> Option<f64> {
        let weights: Vec<f64> = q
            .iter()
            .zip(&r.q)
            .map(|(a, b)| (a - b).abs() + BOUND_MARGIN * a.abs())
            .collect();
        let reach_all: f64 = weights.iter().zip(&index.mode_max).map(|(w, b)| w * b).sum();
        if !reach_all.is_finite() {
            return None;
        }
        let limit = self.counts.len() / CANDIDATE_SHARE;
        let (mut best, mut evaluated) = (f64::NEG_INFINITY, 0);
        for &n in &r.order {
            let n = n as usize;
            let base = r.base[n];
            if base + reach_all < best {
                break;
            }
            let reach = base + index.weighted(n, &weights);
            if reach >= best {
                evaluated += 1;
                if evaluated > limit {
                    return None;
                }
                best = best.max(self.node_von_mises(index, q, n));
            }
        }
        best.is_finite().then_some(best)
    }

    /// The averaged von Mises stress of mesh node `n` for the amplitudes `q`, summed exactly as
    /// [`ReducedBody::nodal_stress`] sums it (the same operations in the same order: the same bits).
    fn node_von_mises(&self, index: &NodeBounds, q: &[f64], n: usize) -> f64 {
        let len = 4 * self.nodes.len();
        let mut sum = 0.0;
        for &en in &index.members[index.starts[n]..index.starts[n + 1]] {
            let mut v = [0.0; 4];
            for (k, &a) in q.iter().enumerate() {
                if a != 0.0 {
                    let x = &self.values[k * len + 4 * en..k * len + 4 * en + 4];
                    for c in 0..4 {
                        v[c] += a * x[c];
                    }
                }
            }
            sum += von_mises([v[0], v[1], v[2]], v[3]);
        }
        sum / self.counts[n]
    }
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
            let (clearance, _) = self.clearances(s.theta, &s.q, wall.face_x);
            for (pt, &(low, _)) in self.arc.iter().zip(&clearance) {
                if low > 0.0 {
                    continue;
                }
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

    /// Bounds of each arc point's gap to the face `x = face_x` from its rigid position and its
    /// largest elastic displacement `‖Φ_p‖ ‖q‖`, `(lower, upper)` \[m\], and the smallest upper
    /// bound (one of the gaps is at most that): a point whose lower bound is positive has no
    /// force, exactly.
    fn clearances(&self, theta: f64, q: &[f64], face_x: f64) -> (Vec<(f64, f64)>, f64) {
        let qn = dot(q, q).sqrt();
        let (sn, cs) = theta.sin_cos();
        let bounds: Vec<(f64, f64)> = self
            .arc
            .iter()
            .map(|p| {
                let x = cs * p.reference[0] - sn * p.reference[1] - face_x;
                (x - p.bound * qn, x + p.bound * qn)
            })
            .collect();
        let upper = bounds.iter().map(|b| b.1).fold(f64::INFINITY, f64::min);
        (bounds, upper)
    }

    /// A lower bound of the arc's gap to the face `x = face_x` at the turn `theta` and the
    /// amplitudes `q` \[m\]: the least, over the arc points, of the rigid position's gap less the
    /// largest elastic displacement `‖Φ_p‖ ‖q‖`; positive: no point touches.
    pub fn clearance(&self, theta: f64, q: &[f64], face_x: f64) -> f64 {
        self.clearances(theta, q, face_x)
            .0
            .iter()
            .map(|b| b.0)
            .fold(f64::INFINITY, f64::min)
    }

    /// Contact energy \[J\], smallest gap \[m\] and the wall's normal force \[N\] of a state.
    pub fn contact(&self, s: &ReducedState, wall: &WallContact) -> (f64, f64, f64) {
        let (mut energy, mut smallest, mut force) = (0.0, f64::INFINITY, 0.0);
        let (clearance, upper) = self.clearances(s.theta, &s.q, wall.face_x);
        for (pt, &(low, _)) in self.arc.iter().zip(&clearance) {
            // apart, and not the closest: its gap is above the closest point's bound
            if low > 0.0 && low > upper {
                continue;
            }
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

    /// The largest nodal von Mises stress of a state \[Pa\] (see the module doc), the same bits as
    /// [`ReducedBody::nodal_stress`]'s `max_von_mises`, evaluated only where it can be largest:
    /// the nodes walked in the order of their value at the reference state, each one's bound of
    /// [`NodeBounds`] taken, and its exact value where the bound reaches the largest found so
    /// far, until even the bound with every mode at its largest falls short (see `bounded_max`).
    /// Where more than a sixteenth of the nodes would need it (no reference yet, or one far from
    /// this state), every node is evaluated as in `nodal_stress`, and this state becomes the
    /// reference.
    pub fn von_mises_max(&self, s: &ReducedState, reference: &mut StressReference) -> f64 {
        let sm = &self.stress;
        let index = sm.node_bounds();
        let nn = sm.counts.len();
        let modes = index.modes;
        if let Some(r) = &reference.0 {
            if r.q.len() == s.q.len() && modes == s.q.len() && r.base.len() == nn {
                if let Some(max) = sm.bounded_max(index, &s.q, r) {
                    return max;
                }
            }
        }
        let all = self.nodal_stress(s);
        if modes == s.q.len() {
            let size: Vec<f64> = s.q.iter().map(|a| a.abs()).collect();
            let base: Vec<f64> = (0..nn)
                .map(|n| all.von_mises[n] + BOUND_MARGIN * index.weighted(n, &size))
                .collect();
            let mut order: Vec<u32> = (0..nn as u32).filter(|&n| sm.counts[n as usize] > 0.0).collect();
            order.sort_by(|&a, &b| base[b as usize].total_cmp(&base[a as usize]));
            reference.0 = Some(Reference {
                q: s.q.clone(),
                base,
                order,
            });
        }
        all.max_von_mises
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
