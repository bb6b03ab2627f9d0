//! Inertia of a Newmark step as an energy: `Π_m(u) = c/2 (u − ũ)ᵀ M (u − ũ)`, `c = 1/(βΔt²)`.
//!
//! `M_{ai,bk} = δ_ik ∫ ρ t N_a N_b dA` is the consistent mass matrix, integrated once with the
//! degree-6 rule (exact for curved P2 elements) and stored in the values layout of the fixed
//! pattern. The step sets the predictor `ũ` and the factor `c` ([`crate::scheme::newmark`]).

use rayon::prelude::*;

use super::{StepContext, StepStart, Term};
use crate::assembly::Pattern;
use crate::fe::for_each_point;
use crate::mesh::Mesh;
use crate::quadrature::TriangleRule;

/// Nodes (rows) of the node-level mass matrix per parallel task of [`MassMatrix::apply_each`].
const ROWS_PER_TASK: usize = 512;

/// Consistent mass matrix (upper triangle in the pattern's layout).
#[derive(Clone, Debug)]
pub struct MassMatrix {
    /// Values, aligned with the pattern.
    pub values: Vec<f64>,
    /// The same matrix node by node, both triangles, row-compressed: `m_ab = ∫ ρ t N_a N_b dA`
    /// for the neighbours `b` of node `a` (`row_ptr`, `cols`, `node_values`); it acts on both
    /// components alike, a quarter of the pattern's work per product ([`MassMatrix::apply`]).
    row_ptr: Vec<usize>,
    cols: Vec<usize>,
    node_values: Vec<f64>,
}

impl MassMatrix {
    /// Assembles `∫ ρ t N_a N_b dA` (both components).
    pub fn new(mesh: &Mesh, pattern: &Pattern, rho: f64, thickness: f64) -> Self {
        Self::of_bodies(
            pattern,
            &[BodyMass {
                mesh,
                first_element: 0,
                density: rho,
                thickness,
            }],
        )
    }

    /// Assembles the mass matrix of several bodies, each with its own density and thickness.
    pub fn of_bodies(pattern: &Pattern, bodies: &[BodyMass]) -> Self {
        let mut values = crate::assembly::written_zeros(pattern.nnz());
        let rule = TriangleRule::degree6();
        for body in bodies {
            let (rho, thickness) = (body.density, body.thickness);
            let mut ke = [0.0; 144];
            let mut current = usize::MAX;
            let flush = |e: usize, ke: &mut [f64; 144], values: &mut [f64]| {
                pattern.scatter_element(body.first_element + e, ke, values);
                *ke = [0.0; 144];
            };
            for_each_point(body.mesh, &rule, |e, n, _x, w| {
                if e != current {
                    if current != usize::MAX {
                        flush(current, &mut ke, &mut values);
                    }
                    current = e;
                }
                for a in 0..6 {
                    for b in 0..6 {
                        let m = rho * thickness * n[a] * n[b] * w;
                        ke[(2 * a) * 12 + 2 * b] += m;
                        ke[(2 * a + 1) * 12 + 2 * b + 1] += m;
                    }
                }
            });
            if current != usize::MAX {
                flush(current, &mut ke, &mut values);
            }
        }
        // node-level copy from the x-x entries (even row, even column)
        let nodes = pattern.n / 2;
        let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nodes];
        for c in (0..pattern.n).step_by(2) {
            for k in pattern.col_ptr[c]..pattern.col_ptr[c + 1] {
                let r = pattern.row_idx[k];
                if r.is_multiple_of(2) && values[k] != 0.0 {
                    rows[r / 2].push((c / 2, values[k]));
                    if r != c {
                        rows[c / 2].push((r / 2, values[k]));
                    }
                }
            }
        }
        let mut row_ptr = vec![0];
        let (mut cols, mut node_values) = (Vec::new(), Vec::new());
        for mut row in rows {
            row.sort_by_key(|e| e.0);
            for (b, m) in row {
                cols.push(b);
                node_values.push(m);
            }
            row_ptr.push(cols.len());
        }
        Self {
            values,
            row_ptr,
            cols,
            node_values,
        }
    }

    /// `y = M x` for an interleaved vector `x` (both components).
    pub fn apply(&self, x: &[f64], y: &mut [f64]) {
        self.rows_each(0, [x], [y]);
    }

    /// `y_i = M x_i` for `N` interleaved vectors (several: for one, [`MassMatrix::apply`] on one
    /// thread costs less than waking another) in one pass over the matrix, its rows in
    /// parallel blocks of 512 nodes (each product the same numbers, bit for bit,
    /// whatever the threads: a row's sum is one thread's, in the row's order).
    pub fn apply_each<const N: usize>(&self, x: [&[f64]; N], y: [&mut [f64]; N]) {
        let nodes = self.row_ptr.len() - 1;
        // the outputs cut into blocks of rows, block by block
        let mut blocks: Vec<(usize, [&mut [f64]; N])> = Vec::new();
        let mut rest = y.map(Some);
        for first in (0..nodes).step_by(ROWS_PER_TASK) {
            let len = 2 * ROWS_PER_TASK.min(nodes - first);
            let mut block: [Option<&mut [f64]>; N] = std::array::from_fn(|_| None);
            for (r, b) in rest.iter_mut().zip(block.iter_mut()) {
                let (head, tail) = r.take().expect("cut once per block").split_at_mut(len);
                (*b, *r) = (Some(head), Some(tail));
            }
            blocks.push((first, block.map(|b| b.expect("cut above"))));
        }
        blocks
            .into_par_iter()
            .for_each(|(first, ys)| self.rows_each(first, x, ys));
    }

    /// The rows from node `first` on of `M x_i` into `y_i` (as long as `y_i` is).
    fn rows_each<const N: usize>(&self, first: usize, x: [&[f64]; N], y: [&mut [f64]; N]) {
        for (row, a) in (first..first + y[0].len() / 2).enumerate() {
            let (mut sx, mut sy) = ([0.0; N], [0.0; N]);
            for k in self.row_ptr[a]..self.row_ptr[a + 1] {
                let (b, m) = (self.cols[k], self.node_values[k]);
                for i in 0..N {
                    sx[i] += m * x[i][2 * b];
                    sy[i] += m * x[i][2 * b + 1];
                }
            }
            for i in 0..N {
                y[i][2 * row] = sx[i];
                y[i][2 * row + 1] = sy[i];
            }
        }
    }
}

/// One body's part of a [`MassMatrix`]: its elements (`mesh`, numbered from `first_element` in the
/// pattern), its density \[kg/m³\] and thickness \[m\].
#[derive(Clone, Copy, Debug)]
pub struct BodyMass<'a> {
    /// The body's elements over the model's node numbering.
    pub mesh: &'a Mesh,
    /// Index of the body's first element among the pattern's elements.
    pub first_element: usize,
    /// Mass density \[kg/m³\].
    pub density: f64,
    /// Thickness \[m\].
    pub thickness: f64,
}

/// The inertia term of one step.
#[derive(Clone, Debug)]
pub struct Inertia<'m> {
    /// The mass matrix.
    pub mass: &'m MassMatrix,
    /// The pattern it lives in.
    pub pattern: &'m Pattern,
    /// `c = 1/(βΔt²)` \[1/s²\].
    pub factor: f64,
    /// Predictor `ũ` \[m\].
    pub predictor: Vec<f64>,
}

impl Inertia<'_> {
    /// The inertia force `c M (u − ũ)`, handed entry by entry to `add(i, f_i)` as it is made,
    /// and the energy `½ (u − ũ)·c M (u − ũ)`.
    fn force_and_energy(&self, u: &[f64], mut add: impl FnMut(usize, f64)) -> f64 {
        let d: Vec<f64> = u.iter().zip(&self.predictor).map(|(a, b)| a - b).collect();
        let mut md = vec![0.0; d.len()];
        self.mass.apply(&d, &mut md);
        let work = md
            .iter()
            .zip(&d)
            .enumerate()
            .map(|(i, (m, d))| {
                let f = m * self.factor;
                add(i, f);
                f * d
            })
            .sum::<f64>();
        0.5 * work
    }
}

impl Term for Inertia<'_> {
    fn name(&self) -> &'static str {
        "inertia"
    }

    fn energy(&self, u: &[f64], _cx: &StepContext) -> f64 {
        self.force_and_energy(u, |_, _| {})
    }

    fn add_gradient(&self, u: &[f64], cx: &StepContext, g: &mut [f64]) {
        self.energy_gradient(u, cx, g);
    }

    fn energy_gradient(&self, u: &[f64], _cx: &StepContext, g: &mut [f64]) -> f64 {
        self.force_and_energy(u, |i, f| g[i] += f)
    }

    fn add_hessian(&self, _u: &[f64], _cx: &StepContext, _pattern: &Pattern, values: &mut [f64]) {
        values
            .iter_mut()
            .zip(&self.mass.values)
            .for_each(|(k, m)| *k += self.factor * m);
    }

    fn assemble(&self, u: &[f64], cx: &StepContext, pattern: &Pattern, g: &mut [f64], values: &mut [f64]) -> f64 {
        self.add_hessian(u, cx, pattern, values);
        self.energy_gradient(u, cx, g)
    }

    /// Quadratic: the gradient at the midpoint `½(u₀ + u₁)` is an exact discrete gradient.
    fn add_discrete_gradient(
        &self,
        start: &StepStart,
        u1: &[f64],
        cx: &StepContext,
        factor: f64,
        g: &mut [f64],
    ) -> f64 {
        let mid: Vec<f64> = start.u.iter().zip(u1).map(|(a, b)| 0.5 * (a + b)).collect();
        self.force_and_energy(&mid, |i, f| g[i] += factor * f);
        self.energy(u1, cx)
    }
}
