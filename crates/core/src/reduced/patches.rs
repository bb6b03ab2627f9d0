//! The contact patches of the reduced body's basis: where the turning head first touches the
//! wall's face (`touch_points`), and the unit normal tractions on the arc around those points
//! whose static responses are the contact modes (`arc_loads`, see [`super::basis`]).

use crate::model::{Model, CONTACT_BOUNDARY};

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
pub(super) fn arc_loads(model: &Model, ndof: usize, contact: usize) -> Vec<Vec<f64>> {
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
    let ds: Vec<f64> = stations.iter().map(|s| s.ds).collect();
    for (st, length) in stations.iter_mut().zip(edge_lengths(&ds)) {
        st.edge = length;
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
            let offset = patch_offset(k, contact, spacing);
            let mut load = vec![0.0; ndof];
            for st in &stations {
                let da = (st.angle - at.angle + PI).rem_euclid(TAU) - PI;
                let hat = hat(at.radius * da - offset, spacing);
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

/// The length of each edge point's edge, from the points' weighted lengths `ds` as
/// [`crate::fe::for_each_edge_point`] visits them: edge by edge, their `ds` adding up to the
/// edge's length \[m\].
pub(crate) fn edge_lengths(ds: &[f64]) -> Vec<f64> {
    ds.chunks(crate::quadrature::GAUSS3_UNIT.len())
        .flat_map(|edge| {
            let length: f64 = edge.iter().sum();
            std::iter::repeat_n(length, edge.len())
        })
        .collect()
}

/// The centre of patch `k` of `count`, `spacing` apart and centred on the touch point, relative
/// to it \[m\].
pub(crate) fn patch_offset(k: usize, count: usize, spacing: f64) -> f64 {
    (k as f64 - 0.5 * (count - 1) as f64) * spacing
}

/// A patch's hat at the distance `d` from its centre: 1 there, 0 from `spacing` on.
pub(crate) fn hat(d: f64, spacing: f64) -> f64 {
    (1.0 - d.abs() / spacing).max(0.0)
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
