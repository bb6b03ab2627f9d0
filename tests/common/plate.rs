//! Fixtures of the output tests (`common::plate`): a hand-built six-node-triangle mesh of a
//! rectangular plate hanging from the origin, synthetic frames (a rigid swing θ(t) = 0.35 cos(6.6 t)
//! plus a small elastic field) and the synthetic history of their run.
#![allow(dead_code)]

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use pendulum_fem::config::Output;
use pendulum_fem::mesh::{BoundaryEdge, Mesh};
use pendulum_fem::render::plot::History;
use pendulum_fem::render::Frame;
use pendulum_fem::simulation::StepRecord;

/// Plate width and length \[m\].
pub const WIDTH: f64 = 0.03;
/// Plate length \[m\].
pub const LENGTH: f64 = 0.3;

/// A `WIDTH × LENGTH` plate, `x ∈ [−W/2, W/2]`, `y ∈ [−L, 0]`, `nx × ny` rectangles each split
/// into two six-node triangles (counter-clockwise); the top edge is "rotation".
pub fn plate_mesh(nx: usize, ny: usize) -> Mesh {
    let vid = |i: usize, j: usize| j * (nx + 1) + i;
    let mut nodes: Vec<[f64; 2]> = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            nodes.push([
                -WIDTH / 2.0 + WIDTH * i as f64 / nx as f64,
                -LENGTH * j as f64 / ny as f64,
            ]);
        }
    }
    let num_vertices = nodes.len();
    let mut corner_tris = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            // j grows downwards (y decreasing): (i, j+1) is below (i, j).
            let (a, b, c, d) = (vid(i, j + 1), vid(i + 1, j + 1), vid(i + 1, j), vid(i, j));
            corner_tris.push([a, b, c]);
            corner_tris.push([a, c, d]);
        }
    }
    let mut mid: HashMap<(usize, usize), usize> = HashMap::new();
    let mut count: HashMap<(usize, usize), usize> = HashMap::new();
    let mut triangles = Vec::new();
    for t in &corner_tris {
        let mut tri = [t[0], t[1], t[2], 0, 0, 0];
        for (k, (p, q)) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])].into_iter().enumerate() {
            let key = (p.min(q), p.max(q));
            *count.entry(key).or_default() += 1;
            let n = *mid.entry(key).or_insert_with(|| {
                nodes.push([(nodes[p][0] + nodes[q][0]) / 2.0, (nodes[p][1] + nodes[q][1]) / 2.0]);
                nodes.len() - 1
            });
            tri[3 + k] = n;
        }
        triangles.push(tri);
    }
    let mut boundary_edges = Vec::new();
    for (ti, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (p, q) = (t[k], t[(k + 1) % 3]);
            if count[&(p.min(q), p.max(q))] == 1 {
                let top = nodes[p][1] == 0.0 && nodes[q][1] == 0.0;
                boundary_edges.push(BoundaryEdge {
                    nodes: [p, q, t[3 + k]],
                    name: usize::from(!top),
                    triangle: ti,
                    local_edge: k,
                });
            }
        }
    }
    Mesh {
        nodes,
        num_vertices,
        triangles,
        boundary_edges,
        boundary_names: vec!["rotation".into(), "default".into()],
        region_name: "pendulum".into(),
        order: 2,
    }
}

/// θ(t) of the synthetic swing \[rad\].
pub fn theta(t: f64) -> f64 {
    0.35 * (6.6 * t).cos()
}

/// Owned arrays of one synthetic frame.
pub struct FrameData {
    pub step: usize,
    pub time: f64,
    pub theta: f64,
    pub displacement: Vec<[f64; 2]>,
    pub velocity: Vec<[f64; 2]>,
    pub acceleration: Vec<[f64; 2]>,
    pub von_mises: Vec<f64>,
    pub cauchy: Vec<[f64; 3]>,
}

impl FrameData {
    pub fn frame(&self) -> Frame<'_> {
        Frame {
            step: self.step,
            time: self.time,
            theta: self.theta,
            displacement: &self.displacement,
            velocity: &self.velocity,
            acceleration: &self.acceleration,
            von_mises: &self.von_mises,
            cauchy: &self.cauchy,
        }
    }
}

/// The synthetic state at `step` (time `step · dt`): rigid rotation by θ plus an elastic stretch
/// of about 1e-7 m that breathes with the swing, and a von Mises field largest at the hinge.
pub fn synthetic_frame(mesh: &Mesh, step: usize, dt: f64) -> FrameData {
    let t = step as f64 * dt;
    let th = theta(t);
    let omega = -0.35 * 6.6 * (6.6 * t).sin();
    let alpha = -0.35 * 6.6 * 6.6 * (6.6 * t).cos();
    let (s, c) = th.sin_cos();
    let breathe = 1.0 + 0.5 * (13.2 * t).cos();
    let mut d = FrameData {
        step,
        time: t,
        theta: th,
        displacement: vec![],
        velocity: vec![],
        acceleration: vec![],
        von_mises: vec![],
        cauchy: vec![],
    };
    for x in &mesh.nodes {
        let depth = -x[1] / LENGTH; // 0 at the hinge, 1 at the tip
        let e_ref = [2e-8 * x[0] / WIDTH * depth, -1e-7 * depth * (2.0 - depth) * breathe];
        let e = [c * e_ref[0] - s * e_ref[1], s * e_ref[0] + c * e_ref[1]];
        let r = [c * x[0] - s * x[1], s * x[0] + c * x[1]];
        d.displacement.push([r[0] - x[0] + e[0], r[1] - x[1] + e[1]]);
        d.velocity.push([-omega * r[1], omega * r[0]]);
        d.acceleration.push([
            -alpha * r[1] - omega * omega * r[0],
            alpha * r[0] - omega * omega * r[1],
        ]);
        let vm = 2e6 * (1.0 - depth) * breathe + 1e5 * (x[0] / WIDTH + 0.5);
        d.von_mises.push(vm);
        d.cauchy.push([0.1 * vm, vm, 0.05 * vm]);
    }
    d
}

/// The history of a synthetic run of `steps` steps of `dt` (the swing of the frames; its records'
/// energies, as a run's `results.csv` would hold them).
pub fn synthetic_history(steps: usize, dt: f64) -> History {
    let (m, lc, inertia, g) = (0.7, 0.15, 0.021, 9.81);
    let records: Vec<StepRecord> = (0..=steps)
        .map(|k| {
            let t = k as f64 * dt;
            let th = theta(t);
            let omega = -0.35 * 6.6 * (6.6 * t).sin();
            let kinetic = 0.5 * inertia * omega * omega;
            let gravity = -m * g * lc * th.cos();
            let strain = 3e-7 * (1.0 + 0.5 * (13.2 * t).cos());
            StepRecord {
                step: k,
                time: t,
                theta: th,
                omega,
                kinetic,
                strain,
                gravity,
                total: kinetic + gravity + strain,
                hinge_force: [0.1, 6.9],
                von_mises_max: 2.1e6,
                newton_iterations: if k == 0 { 0 } else { 3 },
                ..Default::default()
            }
        })
        .collect();
    History::of_records(&records)
}

/// Output settings with every flag on.
pub fn all_outputs() -> Output {
    Output {
        every: 1,
        ..Output::default()
    }
}

/// Runs the writers over `steps` synthetic steps, with their history.
pub fn run(dir: &Path, mesh: &Mesh, output: &Output, steps: usize, dt: f64) -> Vec<PathBuf> {
    use pendulum_fem::render::FrameWriters;
    let mut w = FrameWriters::new(dir, mesh, output, None).unwrap();
    for step in 0..=steps {
        w.frame(&synthetic_frame(mesh, step, dt).frame()).unwrap();
    }
    w.finish(&synthetic_history(steps, dt)).unwrap()
}
