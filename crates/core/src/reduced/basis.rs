//! The reduced body's modes and operators, built once from the full model.
//!
//! **The frame conditions** `C φ = 0` (three rows): the hinge's two mean displacements and the
//! mean-axis (Tisserand) condition `(M J X)ᵀ φ = 0`: the elastic displacement carries no angular
//! momentum about the pivot in the frame, so the frame turns with the body as a whole. They hold
//! the frame statically determinate: no displacement of the body is restrained beyond its rigid
//! motion, so the static response to any load balanced by the frame is an elastic deformation
//! that the frame carries.
//!
//! *Why the mean axis and not the hinge edge.* A frame fixed to the hinge edge's best-fit rotation
//! (the torque's hub angle) makes the body's rotation about the short edge an elastic mode: its
//! coupling `d = ΦᵀMJX` takes almost all of `I₀` (`I₀ − |d|² = 3.6e-5 I₀` on the tutorial mesh) and,
//! for a soft body (E = 1 MPa), the quasi-static response turns the body 0.06 rad about the edge
//! and grows past the linear modes' reach within 0.4 s of a 45° swing, where Newton fails. In the
//! mean-axis frame `d = 0`, the rotation of the body is the frame's, and the same run keeps its
//! strain energy within a few per cent of the full model's. The price is that the hub angle is
//! `θ + h·q` (`h` the hinge edge's best-fit rotation of the modes, [`HubAngle`]), linear in `q`.
//!
//! **The modes** (Craig–Bampton-type for this determinate interface):
//! * the lowest `normal` fixed-frame normal modes, `K φ = ω² M φ`, `C φ = 0`;
//! * static correction modes `K φ = f`, `C φ = 0` for the loads the normal modes represent
//!   poorly: gravity in the frame's two directions (`f = M e_x`, `M e_y`), the centrifugal load
//!   (`f = M X`), the torque's couple on the hinge edge (`f = ∂θ_hub/∂u`; the angular
//!   acceleration's load `M J X` is the mean-axis row itself and is carried by the frame), and,
//!   with a wall, unit normal tractions on the head's arc in `contact` overlapping hat-shaped
//!   patches half an edge apart around each point where the turning body first touches the wall
//!   (`patches.rs`: `touch_points`, and `arc_loads` says why there);
//! * a Rayleigh–Ritz step on their span: M-orthonormal and K-diagonal, `ΦᵀMΦ = 1`,
//!   `ΦᵀKΦ = diag(λ)`, near-dependent vectors dropped.
//!
//! `K` is the elastic tangent at `u = 0` \[N/m\], `M` the consistent mass \[kg\].

use rayon::prelude::*;

use super::{ArcPoint, ProxyModes, ReducedBody, StressModes};
use crate::error::Error;
use crate::linsolve::Cholesky;
use crate::modal::constrained::dot;
use crate::modal::{constrained_modes_on, constrained_static_on, rest_shift, stiffness_at_rest};
use crate::model::{Model, HINGE_BOUNDARY};
use crate::terms::torque::HubAngle;

/// How many modes of each kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BasisSettings {
    /// Fixed-frame normal modes.
    pub normal: usize,
    /// Patches of unit normal traction on the head's arc (with a wall).
    pub contact: usize,
}

/// The three frame rows `C` over the pendulum's `ndof` degrees of freedom: the hinge's two and
/// the mean-axis row `M J X / I₀` (in the hinge rows' units, 1/m, for the Schur complement).
pub fn frame_rows(model: &Model) -> Result<Vec<Vec<f64>>, Error> {
    let ndof = 2 * model.bodies[0].nodes.end;
    let [hx, hy] = model.hinge.dense_rows(ndof);
    let positions = Positions::of(model, ndof);
    let inertia = dot(&positions.x, &positions.mass(model, &positions.x));
    let mut row = positions.mass(model, &positions.jx);
    row.iter_mut().for_each(|v| *v /= inertia);
    Ok(vec![hx, hy, row])
}

/// The reference positions `X` and their quarter turns `J X`, interleaved, and the unit
/// translations, over the pendulum's degrees of freedom.
struct Positions {
    x: Vec<f64>,
    jx: Vec<f64>,
    ex: Vec<f64>,
    ey: Vec<f64>,
}

impl Positions {
    fn of(model: &Model, ndof: usize) -> Self {
        let nodes = &model.mesh.nodes[..ndof / 2];
        Self {
            x: nodes.iter().flat_map(|p| [p[0], p[1]]).collect(),
            jx: nodes.iter().flat_map(|p| [-p[1], p[0]]).collect(),
            ex: (0..ndof).map(|i| if i % 2 == 0 { 1.0 } else { 0.0 }).collect(),
            ey: (0..ndof).map(|i| if i % 2 == 1 { 1.0 } else { 0.0 }).collect(),
        }
    }

    /// `M v`.
    fn mass(&self, model: &Model, v: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; v.len()];
        model.mass.apply(v, &mut y);
        y
    }
}

/// The hinge edge's best-fit rotation per unit displacement, `∂θ_hub/∂u` at rest \[1/m\], over
/// the pendulum's `ndof` degrees of freedom: the torque's couple per unit moment.
fn hub_row(model: &Model, ndof: usize) -> Result<Vec<f64>, Error> {
    let hub = HubAngle::new(&model.bodies[0].mesh, HINGE_BOUNDARY)?;
    let mut row = vec![0.0; ndof];
    for (k, &n) in hub.nodes.iter().enumerate() {
        row[2 * n] = -hub.wy[k] / hub.c0;
        row[2 * n + 1] = hub.wx[k] / hub.c0;
    }
    Ok(row)
}

/// Symmetric eigen-decomposition of the dense `n × n` matrix `a` (row-major) by cyclic Jacobi
/// rotations: eigenvalues and the eigenvectors as the columns of `v`.
pub(crate) fn jacobi_eigen(a: &mut [f64], n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut v = vec![0.0; n * n];
    for i in 0..n {
        v[i * n + i] = 1.0;
    }
    for _sweep in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i * n + j].powi(2))
            .sum();
        let total: f64 = a.iter().map(|x| x * x).sum();
        if off <= 1e-30 * total {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = a[p * n + q];
                if apq == 0.0 {
                    continue;
                }
                let theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let (akp, akq) = (a[k * n + p], a[k * n + q]);
                    a[k * n + p] = c * akp - s * akq;
                    a[k * n + q] = s * akp + c * akq;
                }
                for k in 0..n {
                    let (apk, aqk) = (a[p * n + k], a[q * n + k]);
                    a[p * n + k] = c * apk - s * aqk;
                    a[q * n + k] = s * apk + c * aqk;
                }
                for k in 0..n {
                    let (vkp, vkq) = (v[k * n + p], v[k * n + q]);
                    v[k * n + p] = c * vkp - s * vkq;
                    v[k * n + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    ((0..n).map(|i| a[i * n + i]).collect(), v)
}

/// The static loads of the correction modes (see the module doc).
fn correction_fields(model: &Model, ndof: usize, contact: usize) -> Result<Vec<Vec<f64>>, Error> {
    let p = Positions::of(model, ndof);
    let mut out: Vec<Vec<f64>> = [&p.ex, &p.ey, &p.x].iter().map(|f| p.mass(model, f)).collect();
    out.push(hub_row(model, ndof)?);
    out.extend(super::patches::arc_loads(model, ndof, contact));
    Ok(out)
}

/// The Rayleigh–Ritz basis of the span of `vectors` (each of length `ndof`): M-orthonormal (each
/// vector in turn orthogonalised against those before it, twice, and dropped when less than 1e-8
/// of it is left) and K-diagonal, `K` applied by `stiffness(b, y)` (`y = K b`); the shapes with
/// their `λ = φᵀKφ`, ascending.
pub(crate) fn ritz(
    vectors: impl Iterator<Item = Vec<f64>>,
    ndof: usize,
    mass: &crate::terms::inertia::MassMatrix,
    stiffness: impl Fn(&[f64], &mut [f64]) + Sync,
) -> (Vec<Vec<f64>>, Vec<f64>) {
    let mut basis: Vec<Vec<f64>> = Vec::new();
    // M b of every basis vector
    let mut mass_basis: Vec<Vec<f64>> = Vec::new();
    let mut mv = vec![0.0; ndof];
    for mut v in vectors {
        mass.apply(&v, &mut mv);
        let norm0 = dot(&v, &mv).sqrt();
        if norm0.is_nan() || norm0 <= 0.0 {
            continue;
        }
        for _pass in 0..2 {
            for (b, mb) in basis.iter().zip(&mass_basis) {
                let c = dot(&v, mb);
                v.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
            }
        }
        mass.apply(&v, &mut mv);
        let norm = dot(&v, &mv).sqrt();
        if norm > 1e-8 * norm0 {
            v.iter_mut().for_each(|x| *x /= norm);
            basis.push(v);
            mass_basis.push(mv.iter().map(|x| x / norm).collect());
        }
    }
    let n = basis.len();
    let kb: Vec<Vec<f64>> = basis
        .par_iter()
        .map(|b| {
            let mut y = vec![0.0; ndof];
            stiffness(b, &mut y);
            y
        })
        .collect();
    // symmetric: each pair once (the sum of the two products is the same either way round)
    let mut kr = vec![0.0; n * n];
    for i in 0..n {
        for j in i..n {
            let k = 0.5 * (dot(&basis[i], &kb[j]) + dot(&basis[j], &kb[i]));
            (kr[i * n + j], kr[j * n + i]) = (k, k);
        }
    }
    let (lambda, vecs) = jacobi_eigen(&mut kr, n);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| lambda[a].total_cmp(&lambda[b]));
    let shapes = order
        .iter()
        .map(|&k| {
            let mut phi = vec![0.0; ndof];
            for (i, b) in basis.iter().enumerate() {
                let c = vecs[i * n + k];
                phi.iter_mut().zip(b).for_each(|(x, y)| *x += c * y);
            }
            phi
        })
        .collect();
    (shapes, order.iter().map(|&k| lambda[k]).collect())
}

impl ReducedBody {
    /// Builds the reduced body of the pendulum of `model` (its first body) from the normal modes
    /// `normal` (any basis of fixed-frame modes, each satisfying [`frame_rows`]) and the static
    /// correction modes of `settings`.
    pub fn build(model: &Model, normal: Vec<Vec<f64>>, settings: BasisSettings) -> Result<Self, Error> {
        let rest = Rest::of(model, settings)?;
        let statics = rest.static_modes(model)?;
        Self::from_modes(model, &rest, normal, statics)
    }

    /// The body of the normal modes `normal` and the static modes `statics`, both satisfying the
    /// frame rows, on the stiffness at rest.
    fn from_modes(model: &Model, rest: &Rest, normal: Vec<Vec<f64>>, statics: Vec<Vec<f64>>) -> Result<Self, Error> {
        let ndof = 2 * model.bodies[0].nodes.end;
        let pattern = &model.pattern;
        // the normal modes first, then what each static mode adds
        let (shapes, stiffness) = ritz(normal.into_iter().chain(statics), ndof, &model.mass, |b, y| {
            pattern.sym_matvec(&rest.stiffness, b, y)
        });
        Self::from_shapes(model, shapes, stiffness)
    }

    /// The operators of the module doc for M-orthonormal `shapes` with squared frequencies
    /// `stiffness`.
    fn from_shapes(model: &Model, shapes: Vec<Vec<f64>>, stiffness: Vec<f64>) -> Result<Self, Error> {
        let ndof = shapes.first().map_or(2 * model.bodies[0].nodes.end, Vec::len);
        let pos = Positions::of(model, ndof);
        let (mx, mjx, mex, mey) = (
            pos.mass(model, &pos.x),
            pos.mass(model, &pos.jx),
            pos.mass(model, &pos.ex),
            pos.mass(model, &pos.ey),
        );
        let apply = |v: &[f64]| pos.mass(model, v);
        let hub = hub_row(model, ndof)?;
        let n = shapes.len();
        let b: Vec<f64> = shapes.iter().map(|p| dot(p, &mx)).collect();
        let d: Vec<f64> = shapes.iter().map(|p| dot(p, &mjx)).collect();
        let hub: Vec<f64> = shapes.iter().map(|p| dot(p, &hub)).collect();
        // G_ij = φ_iᵀ Jᵀ M φ_j = −(J φ_i)ᵀ M φ_j
        let mphi: Vec<Vec<f64>> = shapes.par_iter().map(|p| apply(p)).collect();
        let mut g = vec![0.0; n * n];
        for i in 0..n {
            let jp: Vec<f64> = shapes[i].chunks_exact(2).flat_map(|c| [-c[1], c[0]]).collect();
            for j in 0..n {
                g[i * n + j] = -dot(&jp, &mphi[j]);
            }
        }
        let arc = model
            .wall
            .as_ref()
            .map(|w| {
                w.arc_points()
                    .map(|(nodes, basis, weight)| {
                        let mut reference = [0.0; 2];
                        let mut modes = [vec![0.0; n], vec![0.0; n]];
                        for a in 0..3 {
                            reference[0] += basis[a] * model.mesh.nodes[nodes[a]][0];
                            reference[1] += basis[a] * model.mesh.nodes[nodes[a]][1];
                            for k in 0..n {
                                modes[0][k] += basis[a] * shapes[k][2 * nodes[a]];
                                modes[1][k] += basis[a] * shapes[k][2 * nodes[a] + 1];
                            }
                        }
                        let bound = (dot(&modes[0], &modes[0]) + dot(&modes[1], &modes[1])).sqrt();
                        ArcPoint {
                            reference,
                            modes,
                            weight,
                            bound,
                        }
                    })
                    .collect()
            })
            .unwrap_or_default();
        let body = &model.bodies[0];
        let proj = &model.projection;
        let proxy = ProxyModes {
            polar: proj.polar,
            cos: shapes.iter().map(|p| dot(p, &proj.cos_weights[..ndof])).collect(),
            sin: shapes.iter().map(|p| dot(p, &proj.sin_weights[..ndof])).collect(),
        };
        // each mode's small-strain stress, the modes on the pool's threads
        let (element_nodes, counts) = body.stress.element_nodes();
        let nen = element_nodes.len();
        let slope = body.material.stress_slope_at_rest();
        let mut values = vec![0.0; nen * 4 * n];
        values.par_chunks_mut(nen * 4).zip(&shapes).for_each(|(values, phi)| {
            let stresses = body.stress.element_node_small_strain_stresses(&slope, phi);
            values.copy_from_slice(stresses.as_flattened());
        });
        let stress = StressModes {
            values,
            nodes: element_nodes,
            counts: counts.to_vec(),
            ..Default::default()
        };
        Ok(Self {
            proxy,
            stress,
            inertia: dot(&pos.x, &mx),
            b,
            d,
            hub,
            g,
            s0: [dot(&pos.ex, &mx), dot(&pos.ey, &mx)],
            s: [
                shapes.iter().map(|p| dot(p, &mex)).collect(),
                shapes.iter().map(|p| dot(p, &mey)).collect(),
            ],
            mass: dot(&pos.ex, &mex),
            arc,
            reference: pos.x.clone(),
            shapes,
            stiffness,
        })
    }
}

/// What both kinds of modes start from, made once: the stiffness at rest, the frame rows, the
/// static loads and the symbolic analysis of the pattern (each kind factorises a matrix of its
/// own on it).
struct Rest {
    stiffness: Vec<f64>,
    rows: Vec<Vec<f64>>,
    loads: Vec<Vec<f64>>,
    analysis: Cholesky,
}

impl Rest {
    /// The pendulum of `model` at rest with the loads of `settings`; a model with more than the
    /// pendulum is refused. The ordering needs only the pattern: it is made beside the rest.
    fn of(model: &Model, settings: BasisSettings) -> Result<Self, Error> {
        let ndof = 2 * model.bodies[0].nodes.end;
        if model.pattern.n != ndof {
            return Err(Error::Config(format!(
                "the reduced body is built from a model of the pendulum alone ({ndof} unknowns), not one of {} \
                 (a deformable wall is reduced beside it, crate::reduced::wall)",
                model.pattern.n
            )));
        }
        let (analysis, rest) = rayon::join(
            || Cholesky::new(&model.pattern),
            || -> Result<_, Error> {
                Ok((
                    stiffness_at_rest(model),
                    frame_rows(model)?,
                    correction_fields(model, ndof, settings.contact)?,
                ))
            },
        );
        let (stiffness, rows, loads) = rest?;
        Ok(Self {
            stiffness,
            rows,
            loads,
            analysis: analysis?,
        })
    }

    /// The lowest `n` fixed-frame normal modes of the pendulum (see the module doc).
    fn normal_modes(&self, model: &Model, n: usize) -> Result<Vec<Vec<f64>>, Error> {
        let modes = constrained_modes_on(
            self.analysis.sibling()?,
            &model.pattern,
            &self.stiffness,
            &model.mass,
            &self.rows,
            n,
            rest_shift(model),
        )?;
        Ok(modes.shapes)
    }

    /// The static correction modes (see the module doc).
    fn static_modes(&self, model: &Model) -> Result<Vec<Vec<f64>>, Error> {
        constrained_static_on(
            self.analysis.sibling()?,
            &model.pattern,
            &self.stiffness,
            &self.rows,
            &self.loads,
        )
    }
}

/// The reduced body of `model` with the modes of its `[model]` section.
///
/// The normal and the static modes each factorise a matrix of their own and do not depend on
/// each other: they are computed side by side, on two threads.
pub fn for_model(model: &Model) -> Result<ReducedBody, Error> {
    let settings = BasisSettings {
        normal: model.config.model.modes,
        contact: model.config.model.contact_modes,
    };
    let rest = Rest::of(model, settings)?;
    let (normal, statics) = rayon::join(
        || rest.normal_modes(model, settings.normal),
        || rest.static_modes(model),
    );
    ReducedBody::from_modes(model, &rest, normal?, statics?)
}
