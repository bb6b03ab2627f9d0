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
//!   (`touch_points`; `arc_loads` says why there);
//! * a Rayleigh–Ritz step on their span: M-orthonormal and K-diagonal, `ΦᵀMΦ = 1`,
//!   `ΦᵀKΦ = diag(λ)`, near-dependent vectors dropped.
//!
//! `K` is the elastic tangent at `u = 0` \[N/m\], `M` the consistent mass \[kg\].

use super::{ArcPoint, ProxyModes, ReducedBody, StressModes};
use crate::modal::{constrained_modes, constrained_static, rest_shift, stiffness_at_rest};
use crate::simulation::{Model, CONTACT_BOUNDARY, HINGE_BOUNDARY};
use crate::terms::torque::HubAngle;
use crate::Error;

/// How many modes of each kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BasisSettings {
    /// Fixed-frame normal modes.
    pub normal: usize,
    /// Patches of unit normal traction on the head's arc (with a wall).
    pub contact: usize,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
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
    out.extend(arc_loads(model, ndof, contact));
    Ok(out)
}

/// One quadrature point of the head's arc, as the contact patches see it.
struct Station {
    nodes: [usize; 3],
    basis: [f64; 3],
    position: [f64; 2],
    ds: f64,
    /// The length of the point's edge \[m\].
    edge: f64,
    /// Distance from the head's centre \[m\], polar angle about it \[rad\], and the unit vector
    /// towards it (the wall's push).
    radius: f64,
    angle: f64,
    inward: [f64; 2],
}

/// The arc points where the undeformed body, turned rigidly about the pivot, first touches the
/// face `x = x_w` at either end of each range of angles it can take without crossing it.
///
/// Point `p` at `X_p = r_p (cos α_p, sin α_p)` is behind the face on the turn `θ` when
/// `r_p cos(α_p + θ) < x_w`: for `c = x_w / r_p ∈ (−1, 1]` the open arc of angles
/// `θ ∈ (acos c − α_p, 2π − acos c − α_p)`, never for `c ≤ −1`. An end of a point's arc that lies
/// inside no other point's arc ends a free range, and that point is where the body touches there.
/// A body that is behind the face at every angle (a point with `c > 1`, or arcs covering the
/// circle) has no free range and no touch point.
pub(crate) fn touch_points(positions: &[[f64; 2]], face_x: f64) -> Vec<usize> {
    use std::f64::consts::TAU;
    let mut arcs = Vec::new();
    for (i, p) in positions.iter().enumerate() {
        let r = p[0].hypot(p[1]);
        let c = face_x / r.max(1e-300);
        if c > 1.0 {
            return Vec::new();
        }
        if c > -1.0 {
            let start = (c.acos() - p[1].atan2(p[0])).rem_euclid(TAU);
            arcs.push((start, TAU - 2.0 * c.acos(), i));
        }
    }
    // strictly inside another point's arc (on the circle)
    let covered = |theta: f64, me: usize| {
        arcs.iter().any(|&(s, len, j)| {
            j != me && {
                let d = (theta - s).rem_euclid(TAU);
                d > 0.0 && d < len
            }
        })
    };
    let mut out = Vec::new();
    for &(s, len, i) in &arcs {
        if !covered(s, i) || !covered(s + len, i) {
            out.push(i);
        }
    }
    out
}

/// Unit normal tractions on hat-shaped patches of the head's arc around each point where the
/// body can first touch the wall ([`touch_points`]): `contact` patches per touch point, centred on
/// it, half the arc's edge length apart there.
///
/// Why there and that close: a stiff contact (1e14 N/m³: 6 µm deep, about 1 mm wide on the tutorial
/// mesh) loads one or two of the arc's quadrature points, and how much of an impact's energy
/// stays in vibration depends on the body's compliance right under them. Patches spread over the
/// whole reachable arc (one per 50 mm with 8) left the head locally too stiff: the first rebound
/// from a 20° swing at 1e14 N/m³ was 15.6° against the full model's 17.42°; 8 patches 1.5 mm
/// apart around the touch point give 17.43°, and 4 to 32 of them, or 4 to 32 normal modes,
/// 17.32°–17.54°. Patches 0.9 to 1.7 mm apart did as well in a trial; 2.9 mm apart gave 17.17°.
///
/// The head's centre, for the arc coordinate and the patches' inward direction, is the mean of the
/// arc's quadrature points (on the tutorial's head, whose arc leaves out where the rod joins it,
/// 5 mm below the circle's centre: the patches' widths are off by less than a tenth).
fn arc_loads(model: &Model, ndof: usize, contact: usize) -> Vec<Vec<f64>> {
    use std::f64::consts::{PI, TAU};
    if contact == 0 || model.wall.is_none() {
        return Vec::new();
    }
    let mesh = &model.bodies[0].mesh;
    let mut stations: Vec<Station> = Vec::new();
    crate::fe::for_each_edge_point(mesh, CONTACT_BOUNDARY, |nodes, basis, position, ds| {
        stations.push(Station {
            nodes,
            basis,
            position,
            ds,
            edge: 0.0,
            radius: 0.0,
            angle: 0.0,
            inward: [0.0; 2],
        });
    });
    if stations.is_empty() {
        return Vec::new();
    }
    // each edge's points come in a row: their ds add up to the edge's length
    for edge in stations.chunks_mut(crate::quadrature::GAUSS3_UNIT.len()) {
        let length: f64 = edge.iter().map(|s| s.ds).sum();
        edge.iter_mut().for_each(|s| s.edge = length);
    }
    let centre = {
        let k = stations.len() as f64;
        let s = stations
            .iter()
            .fold([0.0, 0.0], |a, p| [a[0] + p.position[0], a[1] + p.position[1]]);
        [s[0] / k, s[1] / k]
    };
    for st in &mut stations {
        let r = [st.position[0] - centre[0], st.position[1] - centre[1]];
        st.radius = r[0].hypot(r[1]);
        st.angle = r[1].atan2(r[0]);
        let norm = st.radius.max(1e-300);
        st.inward = [-r[0] / norm, -r[1] / norm];
    }
    let positions: Vec<[f64; 2]> = stations.iter().map(|s| s.position).collect();
    let mut loads = Vec::new();
    for touch in touch_points(&positions, model.config.wall.x) {
        let at = &stations[touch];
        let spacing = 0.5 * at.edge;
        // the patches' centres along the arc, measured as the angle about the head's centre
        // times the touch point's radius (the stations need not come in the arc's order)
        for k in 0..contact {
            let offset = (k as f64 - 0.5 * (contact - 1) as f64) * spacing;
            let mut load = vec![0.0; ndof];
            for st in &stations {
                let da = (st.angle - at.angle + PI).rem_euclid(TAU) - PI;
                let hat = (1.0 - (at.radius * da - offset).abs() / spacing).max(0.0);
                if hat == 0.0 {
                    continue;
                }
                let t = st.inward;
                for a in 0..3 {
                    load[2 * st.nodes[a]] += hat * t[0] * st.basis[a] * st.ds;
                    load[2 * st.nodes[a] + 1] += hat * t[1] * st.basis[a] * st.ds;
                }
            }
            loads.push(load);
        }
    }
    loads
}

/// The Rayleigh–Ritz basis of the span of `vectors` (each of length `ndof`): M-orthonormal (each
/// vector in turn orthogonalised against those before it, twice, and dropped when less than 1e-8
/// of it is left) and K-diagonal, `K` applied by `stiffness(b, y)` (`y = K b`); the shapes with
/// their `λ = φᵀKφ`, ascending.
pub(crate) fn ritz(
    vectors: impl Iterator<Item = Vec<f64>>,
    ndof: usize,
    mass: &crate::terms::inertia::MassMatrix,
    stiffness: impl Fn(&[f64], &mut [f64]),
) -> (Vec<Vec<f64>>, Vec<f64>) {
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut mv = vec![0.0; ndof];
    for mut v in vectors {
        mass.apply(&v, &mut mv);
        let norm0 = dot(&v, &mv).sqrt();
        if norm0.is_nan() || norm0 <= 0.0 {
            continue;
        }
        for _pass in 0..2 {
            for b in &basis {
                mass.apply(b, &mut mv);
                let c = dot(&v, &mv);
                v.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
            }
        }
        mass.apply(&v, &mut mv);
        let norm = dot(&v, &mv).sqrt();
        if norm > 1e-8 * norm0 {
            v.iter_mut().for_each(|x| *x /= norm);
            basis.push(v);
        }
    }
    let n = basis.len();
    let kb: Vec<Vec<f64>> = basis
        .iter()
        .map(|b| {
            let mut y = vec![0.0; ndof];
            stiffness(b, &mut y);
            y
        })
        .collect();
    let mut kr = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            kr[i * n + j] = 0.5 * (dot(&basis[i], &kb[j]) + dot(&basis[j], &kb[i]));
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
        let ndof = 2 * model.bodies[0].nodes.end;
        if model.pattern.n != ndof {
            return Err(Error::Config(format!(
                "the reduced body is built from a model of the pendulum alone ({ndof} unknowns), not one of {} \
                 (a deformable wall is reduced beside it, crate::reduced::wall)",
                model.pattern.n
            )));
        }
        let pattern = &model.pattern;
        let stiffness = stiffness_at_rest(model);
        let rows = frame_rows(model)?;
        let loads = correction_fields(model, ndof, settings.contact)?;
        let statics = constrained_static(pattern, &stiffness, &rows, &loads)?;
        // the normal modes first, then what each static mode adds
        let (shapes, stiffness) = ritz(normal.into_iter().chain(statics), ndof, &model.mass, |b, y| {
            pattern.sym_matvec(&stiffness, b, y)
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
        let mphi: Vec<Vec<f64>> = shapes.iter().map(|p| apply(p)).collect();
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
        // each mode's small-strain stress: a central difference of the law at ±1 µm
        let (element_nodes, counts) = body.stress.element_nodes();
        let nen = element_nodes.len();
        let mut values = vec![0.0; nen * 4 * n];
        for (k, phi) in shapes.iter().enumerate() {
            let amp = phi.iter().fold(0.0f64, |a, b| a.max(b.abs())).max(1e-300);
            let delta = 1e-6 / amp;
            let plus: Vec<f64> = phi.iter().map(|v| delta * v).collect();
            let minus: Vec<f64> = phi.iter().map(|v| -delta * v).collect();
            let sp = body.stress.element_node_stresses(&body.material, &plus);
            let sm = body.stress.element_node_stresses(&body.material, &minus);
            for e in 0..nen {
                for c in 0..4 {
                    values[k * nen * 4 + e * 4 + c] = (sp[e][c] - sm[e][c]) / (2.0 * delta);
                }
            }
        }
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

/// The reduced body of `model` with the modes of its `[model]` section.
pub fn for_model(model: &Model) -> Result<ReducedBody, Error> {
    let settings = BasisSettings {
        normal: model.config.model.modes,
        contact: model.config.model.contact_modes,
    };
    let normal = normal_modes(model, settings.normal)?;
    ReducedBody::build(model, normal, settings)
}

/// The lowest `n` fixed-frame normal modes of the pendulum (see the module doc).
fn normal_modes(model: &Model, n: usize) -> Result<Vec<Vec<f64>>, Error> {
    let stiffness = stiffness_at_rest(model);
    let rows = frame_rows(model)?;
    let modes = constrained_modes(&model.pattern, &stiffness, &model.mass, &rows, n, rest_shift(model))?;
    Ok(modes.shapes)
}

#[cfg(test)]
mod tests {
    use super::touch_points;

    /// The free range and its touch points by brute force: the angles on a fine grid where no
    /// point is behind the face, and at the range's ends the point with the smallest `x`.
    fn sampled(points: &[[f64; 2]], face_x: f64) -> Vec<usize> {
        let n = 200_000;
        let x = |p: [f64; 2], t: f64| p[0] * t.cos() - p[1] * t.sin();
        let free = |t: f64| points.iter().all(|&p| x(p, t) >= face_x);
        let lowest = |t: f64| {
            (0..points.len())
                .min_by(|&a, &b| x(points[a], t).total_cmp(&x(points[b], t)))
                .unwrap()
        };
        let mut out = Vec::new();
        for k in 0..n {
            let (t0, t1) = (
                std::f64::consts::TAU * k as f64 / n as f64,
                std::f64::consts::TAU * (k + 1) as f64 / n as f64,
            );
            match (free(t0), free(t1)) {
                (true, false) => out.push(lowest(t0)),
                (false, true) => out.push(lowest(t1)),
                _ => {}
            }
        }
        out.sort();
        out
    }

    #[test]
    fn the_touch_points_are_where_a_rigid_turn_either_way_first_meets_the_face() {
        // a ring of radius 0.06 m hanging 0.24 m below the pivot, 97 points (none exactly at
        // the touch angles), and faces: touching at rest, 3 cm clear, 2 cm past the pivot (the
        // ring turned right is clear of it), and beyond its reach
        let ring: Vec<[f64; 2]> = (0..97)
            .map(|k| {
                let a = 0.3 + std::f64::consts::TAU * k as f64 / 97.0;
                [0.06 * a.cos(), -0.24 + 0.06 * a.sin()]
            })
            .collect();
        for face in [-0.06, -0.03, -0.2, 0.02] {
            let mut got = touch_points(&ring, face);
            got.sort();
            assert_eq!(got.len(), 2, "face at {face}: {got:?}");
            assert_eq!(got, sampled(&ring, face), "face at {face}");
        }
        assert!(touch_points(&ring, -0.31).is_empty(), "out of reach");
        assert!(touch_points(&ring, 0.5).is_empty(), "behind the face at every angle");
    }
}
