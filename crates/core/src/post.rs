//! Results derived from a state: the rigid-body proxy angle and its rates, energies, stresses.
//!
//! **Proxy angle** (the tutorial's `rigid_body_proxy`): with `r = X` the reference position
//! relative to the pivot,
//!
//! ```text
//! s = ∫ (r_x u_y − r_y u_x) dA / ∫ r·r dA,   c = ∫ r·(r + u) dA / ∫ r·r dA,   θ = atan2(s, c),
//! ```
//!
//! the best-fit rotation of the displaced body about the pivot. Both integrals are linear in `u`
//! and are precomputed as vectors (degree-6 rule, exact on curved P2 elements). `θ` is unwrapped
//! so that it stays continuous past ±180° ([`Unwrap`]).
//!
//! **Rates**: the same best-fit projection applied to the velocity and acceleration fields about the
//! current position `x = X + u`: `ω = ∫ x × v dA / ∫ x·x dA`, `α = ∫ x × a dA / ∫ x·x dA`; exact for a
//! rigid motion (`v = ω e_z × x`, `a = α e_z × x − ω² x`). The integrals use the consistent mass
//! matrix (exact for fields in the P2 space; uniform density cancels).
//!
//! **Stress**: Cauchy `σ = J⁻¹ P Fᵀ`, von Mises as in [`crate::material::von_mises`], evaluated at
//! the six nodes of every element. Nodal fields average the element values; the reported maximum
//! is the largest element-node value (not averaged).

use crate::element::Tri6;
use crate::fe::{for_each_point, FeCache};
use crate::material::{von_mises, Material};
use crate::quadrature::TriangleRule;
use crate::terms::elastic::{deformation_gradient, displacement_gradient};
use crate::{Error, Mesh};

/// Writes into `out` the displacements of `nodes` turned rigidly by `angle` \[rad\] about the
/// pivot (the origin) from `u`: `x' = R(angle) (X + u)`, `u' = x' − X`, with `X` from `reference`.
/// Each node's value is computed from `u` alone, so a node listed twice is turned once; the other
/// entries of `out` are left as they are.
pub fn turn_about_pivot(
    reference: &[[f64; 2]],
    u: &[f64],
    out: &mut [f64],
    nodes: impl IntoIterator<Item = usize>,
    angle: f64,
) {
    let (s, c) = angle.sin_cos();
    for n in nodes {
        let [x, y] = turned(reference[n], [u[2 * n], u[2 * n + 1]], (s, c));
        (out[2 * n], out[2 * n + 1]) = (x, y);
    }
}

/// The displacement of the point at `p` displaced by `u` and then turned about the pivot by the
/// angle of `(sin, cos)`: one node of [`turn_about_pivot`].
#[inline]
pub fn turned(p: [f64; 2], u: [f64; 2], (s, c): (f64, f64)) -> [f64; 2] {
    let x = [p[0] + u[0], p[1] + u[1]];
    [c * x[0] - s * x[1] - p[0], s * x[0] + c * x[1] - p[1]]
}

/// The linear functionals of the proxy angle.
#[derive(Clone, Debug)]
pub struct RigidProjection {
    /// `∂/∂u ∫ (r_x u_y − r_y u_x) dA`.
    pub sin_weights: Vec<f64>,
    /// `∂/∂u ∫ r·u dA`.
    pub cos_weights: Vec<f64>,
    /// `∫ r·r dA` \[m⁴\].
    pub polar: f64,
    /// `∫ dA` \[m²\].
    pub area: f64,
    /// `∫ r dA` \[m³\].
    pub first_moment: [f64; 2],
}

impl RigidProjection {
    /// Precomputes the functionals on `mesh` (pivot at the origin).
    pub fn new(mesh: &Mesh) -> Self {
        let ndof = 2 * mesh.num_nodes();
        let mut sin_weights = crate::assembly::written_zeros(ndof);
        let mut cos_weights = crate::assembly::written_zeros(ndof);
        let (mut polar, mut area, mut first_moment) = (0.0, 0.0, [0.0; 2]);
        for_each_point(mesh, &TriangleRule::degree6(), |e, n, x, w| {
            polar += (x[0] * x[0] + x[1] * x[1]) * w;
            area += w;
            first_moment[0] += x[0] * w;
            first_moment[1] += x[1] * w;
            for (a, &node) in mesh.triangles[e].iter().enumerate() {
                sin_weights[2 * node] -= x[1] * n[a] * w;
                sin_weights[2 * node + 1] += x[0] * n[a] * w;
                cos_weights[2 * node] += x[0] * n[a] * w;
                cos_weights[2 * node + 1] += x[1] * n[a] * w;
            }
        });
        Self {
            sin_weights,
            cos_weights,
            polar,
            area,
            first_moment,
        }
    }

    /// The proxy angle in `(−π, π]` \[rad\].
    pub fn angle(&self, u: &[f64]) -> f64 {
        let s: f64 = self.sin_weights.iter().zip(u).map(|(w, x)| w * x).sum();
        let c: f64 = self.cos_weights.iter().zip(u).map(|(w, x)| w * x).sum();
        best_fit_angle(self.polar + c, s, None)
    }
}

/// The best-fit rotation angle about the pivot of a displaced set of points \[rad\], from its two
/// moments `c = ∫ X·x` and `s = ∫ X × x` (reference positions `X`, current `x`; any positive
/// weighting): `atan2(s, c)`, in `(−π, π]` without a `reference`, else on the branch within π of
/// `reference` (`(c, s)` is turned by `−reference`, `atan2` taken, `reference` added back, so
/// that no large angle enters `atan2`). The proxy angle ([`RigidProjection::angle`]), the
/// torque's hub angle ([`crate::terms::torque::HubAngle::angle_near`]) and the turn between two
/// hub states in its discrete gradient (`c = z₀·z₁`, `s = z₀ × z₁`) are this of their moments.
pub fn best_fit_angle(c: f64, s: f64, reference: Option<f64>) -> f64 {
    match reference {
        None => s.atan2(c),
        Some(reference) => {
            let (sr, cr) = reference.sin_cos();
            // rotate (c, s) by −reference
            let (c1, s1) = (c * cr + s * sr, s * cr - c * sr);
            reference + s1.atan2(c1)
        }
    }
}

/// The angle equal to `angle` modulo 2π that is closest to `reference` \[rad\]: the one unwrapping
/// rule ([`Unwrap`] with the previous value, [`crate::newton::wrap_angle`] with 0).
pub fn unwrap_near(angle: f64, reference: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    angle + tau * ((reference - angle) / tau).round()
}

/// Keeps an angle continuous across the ±π branch cut of `atan2`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Unwrap {
    last: Option<f64>,
}

impl Unwrap {
    /// Starts from a known continuous value.
    pub fn starting_at(theta: f64) -> Self {
        Self { last: Some(theta) }
    }

    /// The continuous angle closest to the previous one that equals `wrapped` modulo 2π.
    pub fn next(&mut self, wrapped: f64) -> f64 {
        let value = match self.last {
            None => wrapped,
            Some(prev) => unwrap_near(wrapped, prev),
        };
        self.last = Some(value);
        value
    }
}

/// Nodal stresses of a state.
#[derive(Clone, Debug, Default)]
pub struct NodalStress {
    /// Averaged Cauchy stress `[σxx, σyy, σxy]` per node \[Pa\].
    pub cauchy: Vec<[f64; 3]>,
    /// Averaged von Mises stress per node \[Pa\].
    pub von_mises: Vec<f64>,
    /// Largest averaged nodal von Mises stress \[Pa\] (the largest of `von_mises`).
    pub max_von_mises: f64,
}

/// Evaluates stresses at element nodes.
#[derive(Clone, Debug)]
pub struct StressRecovery {
    nodal: FeCache,
    triangles: Vec<[usize; 6]>,
    counts: Vec<f64>,
}

impl StressRecovery {
    /// Precomputes basis gradients at the six nodes of every element.
    pub fn new(mesh: &Mesh) -> Result<Self, Error> {
        let rule = TriangleRule {
            points: Tri6::NODES.to_vec(),
            weights: vec![0.0; 6],
            degree: 0,
        };
        let nodal = FeCache::new(mesh, &rule, 1.0)?;
        let mut counts = vec![0.0; mesh.num_nodes()];
        for tri in &mesh.triangles {
            for &n in tri {
                counts[n] += 1.0;
            }
        }
        Ok(Self {
            nodal,
            triangles: mesh.triangles.clone(),
            counts,
        })
    }

    /// Largest nodal von Mises stress \[Pa\]: the maximum over the nodes of the von Mises stress
    /// averaged over the elements that share the node, the very field the frames show (ParaView,
    /// animations, viewer), so every output reports one largest value. (The largest unaveraged
    /// element-node value is higher where the stress jumps between elements: 1.19e5 against
    /// 9.07e4 Pa at the hinge corners of the default run; that jump is discretisation error.)
    pub fn max_von_mises(&self, material: &Material, u: &[f64]) -> f64 {
        use rayon::prelude::*;
        // element-node values in parallel, summed per node in element order (deterministic)
        let values: Vec<[f64; 6]> = self
            .triangles
            .par_iter()
            .enumerate()
            .map(|(e, tri)| {
                std::array::from_fn(|a| {
                    let f = deformation_gradient(tri, &self.nodal.grads[e * 6 + a], u);
                    let (s, szz) = material.cauchy_stress(&f);
                    von_mises(s, szz)
                })
            })
            .collect();
        let mut sum = vec![0.0; self.counts.len()];
        for (tri, v) in self.triangles.iter().zip(&values) {
            for (&node, x) in tri.iter().zip(v) {
                sum[node] += x;
            }
        }
        sum.iter()
            .zip(&self.counts)
            .filter(|(_, c)| **c > 0.0)
            .map(|(s, c)| s / c)
            .fold(0.0, f64::max)
    }

    /// The small-strain stress `[σxx, σyy, σxy, σzz]` of the displacement `u` at every element
    /// node (six per element, in element order) \[Pa\]: `slope · ∇₀u` with `slope` the law's
    /// derivative at rest ([`Material::stress_slope_at_rest`]). Linear in `u`: the stress of a
    /// mode, for the superposition of modes; what [`StressRecovery::nodal`] averages.
    pub fn element_node_small_strain_stresses(&self, slope: &[[f64; 4]; 4], u: &[f64]) -> Vec<[f64; 4]> {
        let mut out = Vec::with_capacity(6 * self.triangles.len());
        for (e, tri) in self.triangles.iter().enumerate() {
            for a in 0..6 {
                let h = displacement_gradient(tri, &self.nodal.grads[e * 6 + a], u);
                out.push(slope.map(|row| row[0] * h[0] + row[1] * h[1] + row[2] * h[2] + row[3] * h[3]));
            }
        }
        out
    }

    /// The element nodes' mesh nodes (six per element, in element order) and each node's number of
    /// elements.
    pub fn element_nodes(&self) -> (Vec<usize>, &[f64]) {
        (self.triangles.iter().flatten().copied().collect(), &self.counts)
    }

    /// Averaged nodal fields and the maximum.
    pub fn nodal(&self, material: &Material, u: &[f64]) -> NodalStress {
        let nn = self.counts.len();
        let mut out = NodalStress {
            cauchy: vec![[0.0; 3]; nn],
            von_mises: vec![0.0; nn],
            max_von_mises: 0.0,
        };
        for (e, tri) in self.triangles.iter().enumerate() {
            for (a, &node) in tri.iter().enumerate() {
                let f = deformation_gradient(tri, &self.nodal.grads[e * 6 + a], u);
                let (s, szz) = material.cauchy_stress(&f);
                let vm = von_mises(s, szz);
                for i in 0..3 {
                    out.cauchy[node][i] += s[i];
                }
                out.von_mises[node] += vm;
            }
        }
        // nodes of other bodies (no element here) keep zeros
        for (n, c) in self.counts.iter().enumerate().filter(|(_, c)| **c > 0.0) {
            for i in 0..3 {
                out.cauchy[n][i] /= c;
            }
            out.von_mises[n] /= c;
        }
        out.max_von_mises = out.von_mises.iter().copied().fold(0.0, f64::max);
        out
    }
}

/// Period estimate from the zero crossings of `θ(t)` (linear interpolation between samples):
/// `T = 2 (t_last − t_first) / (crossings − 1)`. Streaming: feed samples in time order.
#[derive(Clone, Debug, Default)]
pub struct PeriodEstimator {
    last: Option<(f64, f64)>,
    first_crossing: Option<f64>,
    last_crossing: Option<f64>,
    crossings: usize,
}

impl PeriodEstimator {
    /// Adds the sample `(t, θ)`.
    pub fn push(&mut self, t: f64, theta: f64) {
        if let Some((t0, th0)) = self.last {
            if (th0 < 0.0 && theta >= 0.0) || (th0 > 0.0 && theta <= 0.0) {
                let tc = if theta == th0 {
                    t
                } else {
                    t0 + (t - t0) * th0 / (th0 - theta)
                };
                self.first_crossing.get_or_insert(tc);
                self.last_crossing = Some(tc);
                self.crossings += 1;
            }
        }
        self.last = Some((t, theta));
    }

    /// The period \[s\], once at least two crossings were seen.
    pub fn period(&self) -> Option<f64> {
        match (self.first_crossing, self.last_crossing) {
            (Some(a), Some(b)) if self.crossings >= 2 => Some(2.0 * (b - a) / (self.crossings - 1) as f64),
            _ => None,
        }
    }
}

/// `v` as an output reports it: a negative zero becomes `+0` (`−0 + 0 = +0` in IEEE arithmetic),
/// every other value, NaN included, is unchanged. A force summed from clamped terms
/// (`−k · min(g, 0)` with no penetration) is `−0.0`, which Rust prints as `-0`; files, the FMU and
/// Python show `0` instead.
pub fn unsigned_zero(v: f64) -> f64 {
    v + 0.0
}
