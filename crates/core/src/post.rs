//! Results derived from a state: stresses, the period of a swing. The proxy angle and the other
//! rigid-body measures are in [`crate::rigid`].
//!
//! **Stress**: Cauchy `σ = J⁻¹ P Fᵀ`, von Mises as in [`crate::material::von_mises`], evaluated at
//! the six nodes of every element. Nodal fields average the element values; the reported maximum
//! is the largest element-node value (not averaged).

use crate::element::Tri6;
use crate::error::Error;
use crate::fe::FeCache;
use crate::material::{von_mises, Material};
use crate::mesh::Mesh;
use crate::quadrature::TriangleRule;
use crate::terms::elastic::{deformation_gradient, displacement_gradient};

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
    /// element-node value is higher where the stress jumps between elements; that jump is
    /// discretisation error.)
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
