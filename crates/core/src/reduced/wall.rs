//! The deformable wall beside a reduced pendulum (`model.kind = "reduced"` with
//! `wall.kind = "deformable"`): the contact tutorial's block in a few modes of its own, and its
//! contact with the head.
//!
//! ## Kinematics and energies
//!
//! The block is held on its fixed edges and does not turn, so its displacement is linear in its
//! amplitudes `r` \[√kg·m\]: `u_w = Ψ r`, with `Ψ` M-orthonormal and K-diagonal
//! (`ΨᵀMΨ = 1`, `ΨᵀKΨ = diag(λ)`, `K` the block's elastic tangent at rest \[N/m\]):
//!
//! ```text
//! T_w = ½ |ṙ|²,   V_w = ½ Σ λ_k r_k² + w·r + V_g(0),   w = Ψᵀ ∇V_g      [J]
//! ```
//!
//! (`V_g` the block's weight, linear in `u`). The step ([`super::step`]) adds `r` to the reduced
//! body's coordinates: `ṙ₁ − ṙ₀ + h (Λ r_m + w + Ψᵀ ∇ᵈΠ_c) = 0` with `r_m` the mid-step amplitudes,
//! the midpoint rule of a linear system, exact in energy.
//!
//! ## The basis
//!
//! Static modes of the block, `K ψ = f` on its free degrees of freedom, for its weight and for
//! unit normal pressures on the face in `model.contact_modes` hat-shaped patches half a face
//! element apart, centred at each height where a point of the head that first touches the face
//! (the pendulum basis's touch points) meets it; then a Rayleigh–Ritz step on their span
//! (as the pendulum's, [`super::basis`]). No normal modes of the block: the tutorial's steel
//! block is 25 mm wide and held on three edges; its Ritz frequencies (the default 8 patches) run
//! from about 35 kHz to 1 MHz, far above what an impact of 2 ms excites, so the block
//! answers the head's push quasi-statically and the static modes carry that answer, its
//! compliance under the contact.
//! `tests/reduced.rs` holds its impacts, impulse and rebound to the full model's.
//!
//! ## When it does not apply
//!
//! The run's error estimate ([`super::validity`]) covers the block as the pendulum: the full
//! model's elastic forces of the block at `Ψ r` against `Λ r` ([`ReducedWall::error_estimate`]),
//! the larger of the two estimates counting. And the static basis holds only while the block
//! answers quasi-statically: an impact that lasts less than [`QUASI_STATIC`] periods of the
//! block's lowest Ritz frequency (a soft block, whose inertia then matters) makes the run warn
//! once. Measured at dt = 0.01 s, the first impact of the tutorial's swing against blocks of
//! other Young's moduli (the first rebound and ω leaving the block, against the full model's):
//!
//! | block's E | periods in the impact | rebound off by | ω off by (relative) |
//! |---|---|---|---|
//! | 210 GPa (the tutorial's) | 74 | 1.8e-6° | 2.6e-7 |
//! | 10 GPa | 16 | 5.1e-5° | 2.7e-6 |
//! | 1 GPa | 5.7 (warns) | 1.3e-3° | 6.6e-5 |
//! | 0.1 GPa | 2.9 (warns) | 0.017° | 8.5e-4 |
//!
//! ## Contact
//!
//! The contact is the full model's term on the face ([`WallContact::deformable`]): its discrete
//! gradient `∇ᵈΠ_c` in the displacements of the head's arc nodes and the face's nodes is exact,
//! `∇ᵈΠ_c · Δu = Π_c(u₁) − Π_c(u₀)`. The head's nodes move as `u_a = R(θ)(X_a + Φ_a q) − X_a`, and
//! the product rule for differences, `Δu_a = (R₁ − R₀) ȳ_a + R̄ (y₁ − y₀)_a` with
//! `R₁ − R₀ = 2 sin(Δθ/2) R′(θ_m)`, `ȳ = X + Φ q_m`, `R̄ = ½(R₀ + R₁)`, writes `Δu_a` exactly as a
//! linear map of `(Δθ, Δq)`; the face moves as `Ψ Δr`. The transposed maps carry `∇ᵈΠ_c` to the
//! coordinates, and the identity holds there: the contact does exactly the work of its energy
//! change.

use super::{dot, ReducedBody};
use crate::assembly::Dirichlet;
use crate::error::Error;
use crate::mesh::block::FACE;
use crate::modal::{constrained_static, stiffness_at_rest};
use crate::model::{Model, CONTACT_BOUNDARY};
use crate::rigid::Turn;
use crate::terms::{StepContext, StepStart, Term, WallContact};

/// The fewest periods of the block's lowest Ritz frequency an impact may last for its static
/// basis to apply (see the module doc): a pulse that long drives an oscillator to within a few
/// per cent of its static answer.
pub const QUASI_STATIC: f64 = 10.0;

/// A node of the head's arc with its modal rows.
#[derive(Clone, Debug, PartialEq)]
pub struct HeadNode {
    /// The node's index in the model's mesh.
    pub node: usize,
    /// Reference position `X_a` \[m\].
    pub reference: [f64; 2],
    /// `Φ_a`: the node's displacement in the frame per unit amplitude of each pendulum mode, `x`
    /// then `y` rows.
    pub modes: [Vec<f64>; 2],
}

/// The reduced deformable wall (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct ReducedWall {
    /// The model's first degree of freedom of the block.
    pub first_dof: usize,
    /// `Ψ`, each mode over the block's degrees of freedom.
    pub shapes: Vec<Vec<f64>>,
    /// `λ_k` \[rad²/s²\].
    pub stiffness: Vec<f64>,
    /// `w = Ψᵀ ∇V_g`, the weight's gradient in the amplitudes.
    pub weight: Vec<f64>,
    /// The head's arc nodes.
    pub head: Vec<HeadNode>,
    /// The face's degrees of freedom (the model's numbering) with their rows of `Ψ`.
    pub face: Vec<(usize, Vec<f64>)>,
}

/// The displacements of the head's and the face's nodes at the two ends of a step, and the
/// contact's discrete gradient, each of the model's length (other entries stay zero).
pub(crate) struct Placed {
    u0: Vec<f64>,
    u1: Vec<f64>,
    g: Vec<f64>,
}

/// The contact's discrete gradient in the coordinates: `∂/∂θ`, added into `q` and `r` rows by
/// [`ReducedWall::contact_gradient`], and the wall's force on the head (global frame) \[N\].
pub(crate) struct FaceGradient {
    pub theta: f64,
    pub force: [f64; 2],
}

/// The heights at which the head's touch points (see [`super::basis`]) meet the face `x = x_w`
/// when the body turns rigidly, within the face's span `[low, high]`.
fn touch_heights(model: &Model, low: f64, high: f64) -> Vec<f64> {
    let mut positions = Vec::new();
    crate::fe::for_each_edge_point(&model.bodies[0].mesh, CONTACT_BOUNDARY, |_, _, x, _| positions.push(x));
    let face_x = model.config.wall.x;
    let mut heights: Vec<f64> = super::patches::touch_points(&positions, face_x)
        .into_iter()
        .flat_map(|k| {
            let r2 = positions[k][0].powi(2) + positions[k][1].powi(2);
            let y = (r2 - face_x * face_x).max(0.0).sqrt();
            [-y, y]
        })
        .filter(|y| (low..=high).contains(y))
        .collect();
    heights.sort_by(f64::total_cmp);
    heights.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    heights
}

impl ReducedWall {
    /// The reduced block of `model` (its second body, the deformable wall) beside the reduced
    /// pendulum `body`, with `contact` face patches per touch height (see the module doc).
    pub fn build(model: &Model, body: &ReducedBody, contact: usize) -> Result<Self, Error> {
        let block = model.bodies.get(1).ok_or_else(|| {
            Error::Config("wall.kind = \"deformable\": the model has no second body for the wall".into())
        })?;
        let (pattern, ndof) = (&model.pattern, model.pattern.n);
        let dofs = 2 * block.nodes.start..2 * block.nodes.end;
        // K on the block's free degrees of freedom; the pendulum's held (unit rows) as well
        let mut stiffness = stiffness_at_rest(model);
        Dirichlet::new(pattern, (0..dofs.start).collect()).apply_matrix(&mut stiffness);
        let zero = vec![0.0; ndof];
        let cx = StepContext::at(&zero, 0.0, 0.0, None);
        let mut weight_load = vec![0.0; ndof];
        block.gravity.add_gradient(&zero, &cx, &mut weight_load);
        weight_load.iter_mut().for_each(|v| *v = -*v);
        let mut loads = vec![weight_load];
        // face stations: nodes, edge basis, position, weighted length
        let mut stations = Vec::new();
        crate::fe::for_each_edge_point(&block.mesh, FACE, |nodes, basis, x, ds| {
            stations.push((nodes, basis, x, ds))
        });
        let ds: Vec<f64> = stations.iter().map(|s| s.3).collect();
        let edge_length = super::patches::edge_lengths(&ds);
        let (low, high) = stations.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), s| {
            (l.min(s.2[1]), h.max(s.2[1]))
        });
        for at in touch_heights(model, low, high) {
            let nearest = (0..stations.len())
                .min_by(|&a, &b| (stations[a].2[1] - at).abs().total_cmp(&(stations[b].2[1] - at).abs()))
                .expect("the face has stations");
            let spacing = 0.5 * edge_length[nearest];
            for k in 0..contact {
                let centre = at + super::patches::patch_offset(k, contact, spacing);
                let mut load = vec![0.0; ndof];
                for (nodes, basis, x, ds) in &stations {
                    let hat = super::patches::hat(x[1] - centre, spacing);
                    // the head presses the face towards −x
                    for a in 0..3 {
                        load[2 * nodes[a]] -= hat * basis[a] * ds;
                    }
                }
                loads.push(load);
            }
        }
        // nothing acts on the held degrees of freedom (unit rows of K, which would move)
        loads.iter_mut().for_each(|f| model.fixed.apply_vector(f));
        let statics = constrained_static(pattern, &stiffness, &[], &loads)?;
        let (shapes, lambda) = super::basis::ritz(statics.into_iter(), ndof, &model.mass, |b, y| {
            pattern.sym_matvec(&stiffness, b, y)
        });
        // w = Ψᵀ ∇V_g, the load's negative
        let weight = shapes.iter().map(|s| -dot(s, &loads[0])).collect();
        let head = head_nodes(model, body);
        let face = block
            .mesh
            .nodes_on(FACE)
            .into_iter()
            .flat_map(|n| [2 * n, 2 * n + 1])
            .map(|d| (d, shapes.iter().map(|s| s[d]).collect()))
            .collect();
        Ok(Self {
            first_dof: dofs.start,
            shapes: shapes.into_iter().map(|s| s[dofs.clone()].to_vec()).collect(),
            stiffness: lambda,
            weight,
            head,
            face,
        })
    }

    /// Number of modes.
    pub fn modes(&self) -> usize {
        self.stiffness.len()
    }

    /// The block's error estimate `η` at the amplitudes `r` (as the pendulum's,
    /// [`super::validity`]): `√(Σ ρ_k²/λ_k) / √(Σ λ_k r_k²)` with `ρ = Ψᵀ ∇W(Ψ r) − Λ r`, `W` the
    /// block's hyperelastic strain energy in `model`.
    pub fn error_estimate(&self, model: &Model, r: &[f64]) -> f64 {
        let (mut u, mut scratch) = (vec![0.0; model.pattern.n], vec![0.0; model.pattern.n]);
        self.fields(r, r, &mut u, &mut scratch);
        let cx = StepContext::at(&u, 0.0, 0.0, None);
        let mut force = vec![0.0; model.pattern.n];
        model.bodies[1].elastic.add_gradient(&u, &cx, &mut force);
        super::validity::relative_error(&self.shapes, &self.stiffness, r, &force[self.first_dof..])
    }

    /// The period of the block's lowest Ritz frequency \[s\].
    pub fn lowest_period(&self) -> f64 {
        let lowest = self.stiffness.iter().copied().fold(f64::INFINITY, f64::min);
        std::f64::consts::TAU / lowest.sqrt()
    }

    /// Strain energy `½ Σ λ_k r_k²` \[J\].
    pub fn strain(&self, r: &[f64]) -> f64 {
        0.5 * self.stiffness.iter().zip(r).map(|(l, x)| l * x * x).sum::<f64>()
    }

    /// The block's displacement and velocity `Ψ r`, `Ψ ṙ` into the model's fields `u`, `v`.
    pub fn fields(&self, r: &[f64], rv: &[f64], u: &mut [f64], v: &mut [f64]) {
        let len = self.shapes.first().map_or(0, Vec::len);
        let (u, v) = (
            &mut u[self.first_dof..self.first_dof + len],
            &mut v[self.first_dof..self.first_dof + len],
        );
        u.iter_mut().chain(v.iter_mut()).for_each(|x| *x = 0.0);
        for (psi, (&a, &b)) in self.shapes.iter().zip(r.iter().zip(rv)) {
            u.iter_mut().zip(psi).for_each(|(x, p)| *x += a * p);
            v.iter_mut().zip(psi).for_each(|(x, p)| *x += b * p);
        }
    }

    /// A lower bound of the head's distance to the face in the state `(θ, q, r)` \[m\]: the arc's
    /// clearance of `body` ([`ReducedBody::clearance`]) from the face's line moved towards the
    /// head by three times the face's largest displacement that way (a point past the face's end
    /// meets its end segment's line continued over at most one more segment, the taper, where
    /// that line's displacement is at most three times the nodes'). Positive: the contact's
    /// energy and force are zero.
    pub fn clearance(&self, body: &ReducedBody, theta: f64, q: &[f64], r: &[f64], face_x: f64) -> f64 {
        let face = self
            .face
            .iter()
            .filter(|(d, _)| d % 2 == 0)
            .map(|(_, row)| dot(row, r))
            .fold(0.0f64, f64::max);
        body.clearance(theta, q, face_x + 3.0 * face)
    }

    /// Whether [`ReducedWall::clearance`] is positive: no point of the head can touch the face.
    pub fn surely_apart(&self, body: &ReducedBody, theta: f64, q: &[f64], r: &[f64], face_x: f64) -> bool {
        self.clearance(body, theta, q, r, face_x) > 0.0
    }

    /// A workspace for [`ReducedWall::contact_gradient`], over the model's unknowns (the block's
    /// are the last).
    pub(crate) fn workspace(&self) -> Placed {
        let ndof = self.first_dof + self.shapes.first().map_or(0, Vec::len);
        Placed {
            u0: vec![0.0; ndof],
            u1: vec![0.0; ndof],
            g: vec![0.0; ndof],
        }
    }

    /// Writes the head's and the face's displacements of `(θ, q, r)` into `u` (the same
    /// arithmetic as [`ReducedBody::fields`] and [`ReducedWall::fields`]).
    fn place(&self, theta: f64, q: &[f64], r: &[f64], u: &mut [f64]) {
        let (s, c) = theta.sin_cos();
        for h in &self.head {
            let y = [
                h.reference[0] + dot(&h.modes[0], q),
                h.reference[1] + dot(&h.modes[1], q),
            ];
            u[2 * h.node] = c * y[0] - s * y[1] - h.reference[0];
            u[2 * h.node + 1] = s * y[0] + c * y[1] - h.reference[1];
        }
        for (d, row) in &self.face {
            u[*d] = dot(row, r);
        }
    }

    /// Places the start of a step.
    pub(crate) fn place_start(&self, w: &mut Placed, theta: f64, q: &[f64], r: &[f64]) {
        self.place(theta, q, r, &mut w.u0);
    }

    /// The contact's discrete gradient over the step from the placed start to `(θ₁, q₁, r₁)`, the
    /// turn `turn` from the start's `θ₀` to `θ₁` (see the module doc): adds `∂/∂q` into `grad_q` and `∂/∂r` into `grad_r`, returns `∂/∂θ`
    /// and the wall's force on the head.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn contact_gradient(
        &self,
        contact: &WallContact,
        w: &mut Placed,
        (theta1, turn): (f64, Turn),
        q1: &[f64],
        qm: &[f64],
        r1: &[f64],
        grad_q: &mut [f64],
        grad_r: &mut [f64],
    ) -> FaceGradient {
        self.place(theta1, q1, r1, &mut w.u1);
        let start = StepStart {
            u: &w.u0,
            data: &[],
            dissipation: 0.0,
        };
        let cx = StepContext::at(&w.u1, 0.0, 0.0, None);
        contact.add_discrete_gradient(&start, &w.u1, &cx, 1.0, &mut w.g);
        let Turn { sc, sm, cm, rs, rc } = turn;
        let mut out = FaceGradient {
            theta: 0.0,
            force: [0.0; 2],
        };
        for h in &self.head {
            let (gx, gy) = (w.g[2 * h.node], w.g[2 * h.node + 1]);
            w.g[2 * h.node] = 0.0;
            w.g[2 * h.node + 1] = 0.0;
            if gx == 0.0 && gy == 0.0 {
                continue;
            }
            let y = [
                h.reference[0] + dot(&h.modes[0], qm),
                h.reference[1] + dot(&h.modes[1], qm),
            ];
            // g · sinc R′(θ_m) ȳ, R′(θ) y = (−sin θ y_x − cos θ y_y, cos θ y_x − sin θ y_y)
            out.theta += sc * (gx * (-sm * y[0] - cm * y[1]) + gy * (cm * y[0] - sm * y[1]));
            for (i, gq) in grad_q.iter_mut().enumerate() {
                let (px, py) = (h.modes[0][i], h.modes[1][i]);
                *gq += gx * (rc * px - rs * py) + gy * (rs * px + rc * py);
            }
            out.force[0] -= gx;
            out.force[1] -= gy;
        }
        for (d, row) in &self.face {
            let g = std::mem::take(&mut w.g[*d]);
            if g != 0.0 {
                grad_r.iter_mut().zip(row).for_each(|(a, p)| *a += g * p);
            }
        }
        out
    }

    /// The contact's moment on the pendulum about the pivot in the state `u` of the model \[N m\].
    pub fn contact_moment(&self, contact: &WallContact, u: &[f64]) -> f64 {
        let cx = StepContext::at(u, 0.0, 0.0, None);
        let mut g = vec![0.0; u.len()];
        contact.add_gradient(u, &cx, &mut g);
        self.head
            .iter()
            .map(|h| {
                let x = [h.reference[0] + u[2 * h.node], h.reference[1] + u[2 * h.node + 1]];
                let f = [-g[2 * h.node], -g[2 * h.node + 1]];
                x[0] * f[1] - x[1] * f[0]
            })
            .sum()
    }
}

/// The head's arc nodes of `model` with their rows of the pendulum's modes.
fn head_nodes(model: &Model, body: &ReducedBody) -> Vec<HeadNode> {
    let mesh = &model.bodies[0].mesh;
    mesh.nodes_on(CONTACT_BOUNDARY)
        .into_iter()
        .map(|a| HeadNode {
            node: a,
            reference: mesh.nodes[a],
            modes: [
                body.shapes.iter().map(|s| s[2 * a]).collect(),
                body.shapes.iter().map(|s| s[2 * a + 1]).collect(),
            ],
        })
        .collect()
}
