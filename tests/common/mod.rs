//! Shared fixtures of the integration tests: the repository's root, fresh scratch folders, the
//! CLI built for the test, NaN-checking maxima, the exact rigid pendulum, deterministic fields,
//! mesh checks and the structured fixture of the solver tests. A test file includes it with
//! `mod common;`; its submodules hold the helpers of some files only.
#![allow(dead_code)]

pub mod exact;
pub mod msh;
pub mod plate;
pub mod python;
pub mod tools;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

use pendulum_fem::mesh::BoundaryEdge;
use pendulum_fem::{Config, Mesh};

/// `pendulum-fem run` switches that turn the pictures off (plots, animations, the viewer) and
/// leave `results.csv`, `status.json` and the ParaView frames.
pub const NO_PICTURES: [&str; 6] = [
    "--set",
    "output.plots=false",
    "--set",
    "output.animation=false",
    "--set",
    "output.viewer=false",
];

/// The repository's root (the root package's folder).
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every file and folder of the checkout outside `target/` and `.git/`, relative to the root: what
/// a test compares before and after running what a reader runs, to find files left in the source
/// tree (ignored ones too, as `git status --porcelain --ignored` would list them).
pub fn source_tree_files() -> std::collections::BTreeSet<PathBuf> {
    let root = root();
    let mut found = std::collections::BTreeSet::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for entry in entries.flatten() {
            let path = entry.path();
            let rel = path.strip_prefix(root).unwrap().to_path_buf();
            if rel == Path::new("target") || rel == Path::new(".git") {
                continue;
            }
            if entry.file_type().is_ok_and(|t| t.is_dir()) {
                stack.push(path);
            }
            found.insert(rel);
        }
    }
    found
}

/// Fails naming every entry of the checkout that is in `after` but not in `before` (both from
/// [`source_tree_files`]); `what` says what ran in between.
#[track_caller]
pub fn assert_no_new_files(
    before: &std::collections::BTreeSet<PathBuf>,
    after: &std::collections::BTreeSet<PathBuf>,
    what: &str,
) {
    let new: Vec<String> = after.difference(before).map(|p| p.display().to_string()).collect();
    assert!(new.is_empty(), "{what} left files in the checkout: {}", new.join(", "));
}

/// A fresh, empty folder `<test>-<name>-<process>-<n>` under cargo's temporary folder for
/// integration tests (`target/tmp`): a new one on every call, so that tests running in parallel
/// threads never share one (`<test>` is the test file's name).
pub fn scratch(name: &str) -> PathBuf {
    static CALLS: AtomicUsize = AtomicUsize::new(0);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
        "{}-{name}-{}-{}",
        env!("CARGO_CRATE_NAME"),
        std::process::id(),
        CALLS.fetch_add(1, Ordering::SeqCst)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("scratch folder {}: {e}", dir.display()));
    dir
}

/// The `pendulum-fem` binary cargo built for this test, without the job-array variables of Slurm,
/// PBS and LSF in its environment (`pendulum-fem sweep` reads them to pick its case; a test run
/// inside such a job must not inherit one).
pub fn bin() -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_pendulum-fem"));
    for var in ["SLURM_ARRAY_TASK_ID", "PBS_ARRAY_INDEX", "LSB_JOBINDEX"] {
        cmd.env_remove(var);
    }
    cmd
}

/// The largest and smallest of an iterator of results, checked: `f64::max` and `f64::min` drop a
/// NaN (`f64::max(1.0, NaN) = 1.0`), so a fold with them passes a NaN result unnoticed. These
/// panic on a NaN, and on no values at all (a check over nothing checks nothing).
pub trait Extremes: Iterator<Item = f64> + Sized {
    /// The largest value.
    #[track_caller]
    fn max_of(self) -> f64 {
        extreme(self, f64::max, "largest")
    }

    /// The smallest value.
    #[track_caller]
    fn min_of(self) -> f64 {
        extreme(self, f64::min, "smallest")
    }
}

impl<I: Iterator<Item = f64>> Extremes for I {}

#[track_caller]
fn extreme(values: impl Iterator<Item = f64>, pick: fn(f64, f64) -> f64, what: &str) -> f64 {
    let mut found: Option<f64> = None;
    for (k, v) in values.enumerate() {
        assert!(!v.is_nan(), "the {what} of values that include a NaN (value {k})");
        found = Some(found.map_or(v, |m| pick(m, v)));
    }
    found.unwrap_or_else(|| panic!("the {what} of no values"))
}

/// A deterministic pseudo-random field of `n` values in `(−amp, amp)`: the fractional part of a
/// sine hash of the index shifted by `seed` (seeds differing by less than `n` overlap, shifted).
pub fn wiggle(n: usize, amp: f64, seed: f64) -> Vec<f64> {
    (0..n)
        .map(|i| amp * (((i as f64 + seed) * 12.9898).sin() * 43758.5453).fract())
        .collect()
}

/// Meshes the pendulum of `cfg` and runs it to `time.end`: the simulation and every record (the
/// initial state first).
pub fn simulate(
    cfg: &Config,
) -> (
    pendulum_fem::simulation::Simulation,
    Vec<pendulum_fem::simulation::StepRecord>,
) {
    let mesh = pendulum_fem::mesh::generate(cfg).expect("tutorial mesh");
    let mut sim = pendulum_fem::simulation::Simulation::from_config(cfg, mesh).expect("set-up");
    let mut records = vec![sim.record(0)];
    for _ in 0..cfg.time.steps() {
        records.push(sim.advance().expect("step converges"));
    }
    (sim, records)
}

/// The tutorial configuration (all defaults).
pub fn tutorial() -> Config {
    Config::default()
}

/// A configuration with the given geometry and otherwise default (geometry-derived) sizes.
pub fn with_geometry(rod: f64, head: f64, hole: f64, distance: f64) -> Config {
    let mut cfg = Config::default();
    cfg.geometry.rod_half_width = rod;
    cfg.geometry.head_radius = head;
    cfg.geometry.hole_radius = hole;
    cfg.geometry.head_center_distance = distance;
    cfg
}

/// Edge → number of triangles using it, with `(start, end)` vertex pairs sorted.
pub fn edge_use(mesh: &Mesh) -> HashMap<(usize, usize), usize> {
    let mut m = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *m.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    m
}

/// Twice the signed area of the straight triangle through the vertices.
pub fn signed_area2(mesh: &Mesh, t: usize) -> f64 {
    let [a, b, c] = [0, 1, 2].map(|k| mesh.nodes[mesh.triangles[t][k]]);
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Asserts conformity: interior edges shared by two triangles, boundary edges (exactly the
/// mesh's boundary edges) by one, counter-clockwise triangles, consistent mid nodes, and returns
/// the Euler characteristic `V − E + F`.
pub fn assert_conforming(mesh: &Mesh) -> i64 {
    let uses = edge_use(mesh);
    let boundary: HashMap<(usize, usize), usize> = mesh
        .boundary_edges
        .iter()
        .map(|e| ((e.nodes[0].min(e.nodes[1]), e.nodes[0].max(e.nodes[1])), 1))
        .collect();
    assert_eq!(
        boundary.len(),
        mesh.boundary_edges.len(),
        "a boundary edge is listed twice"
    );
    for (e, &n) in &uses {
        let expected = if boundary.contains_key(e) { 1 } else { 2 };
        assert_eq!(n, expected, "edge {e:?} is used by {n} triangles");
    }
    for t in 0..mesh.triangles.len() {
        assert!(signed_area2(mesh, t) > 0.0, "triangle {t} is not counter-clockwise");
        for &n in &mesh.triangles[t][..3] {
            assert!(n < mesh.num_vertices, "corner node {n} of triangle {t} is not a vertex");
        }
        for &n in &mesh.triangles[t][3..] {
            assert!(
                n >= mesh.num_vertices && n < mesh.num_nodes(),
                "mid node {n} of triangle {t}"
            );
        }
    }
    // One mid node per edge, shared by both triangles.
    let mut mid_of: HashMap<(usize, usize), usize> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let m = *mid_of.entry((a.min(b), a.max(b))).or_insert(t[3 + k]);
            assert_eq!(m, t[3 + k], "edge ({a}, {b}) has two mid nodes");
        }
    }
    assert_eq!(
        mid_of.len(),
        mesh.num_nodes() - mesh.num_vertices,
        "unused or missing mid nodes"
    );
    // Boundary edges: oriented with the domain on the left, pointing at their triangle.
    for e in &mesh.boundary_edges {
        let t = mesh.triangles[e.triangle];
        let k = e.local_edge;
        assert_eq!(
            [t[k], t[(k + 1) % 3], t[3 + k]],
            e.nodes,
            "boundary edge does not match its triangle"
        );
    }
    mesh.num_vertices as i64 - uses.len() as i64 + mesh.triangles.len() as i64
}

/// Length of the straight chord of a boundary edge.
pub fn chord(mesh: &Mesh, nodes: [usize; 3]) -> f64 {
    let (a, b) = (mesh.nodes[nodes[0]], mesh.nodes[nodes[1]]);
    (a[0] - b[0]).hypot(a[1] - b[1])
}

// ---- structured fixture used by the solver tests ----

/// A rectangle `[−w, w] × [−l, 0]` hanging from its top edge (named "rotation"; the other sides
/// "default"), `nx × ny` cells each split into two six-node triangles, straight mid-edge nodes.
pub fn hanging_rectangle(w: f64, l: f64, nx: usize, ny: usize) -> Mesh {
    // vertex grid
    let vid = |i: usize, j: usize| j * (nx + 1) + i;
    let mut nodes = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            nodes.push([-w + 2.0 * w * i as f64 / nx as f64, -l * j as f64 / ny as f64]);
        }
    }
    let num_vertices = nodes.len();
    let mut mids = std::collections::HashMap::new();
    let mut mid = |a: usize, b: usize, nodes: &mut Vec<[f64; 2]>| -> usize {
        let key = (a.min(b), a.max(b));
        *mids.entry(key).or_insert_with(|| {
            let p = [(nodes[a][0] + nodes[b][0]) / 2.0, (nodes[a][1] + nodes[b][1]) / 2.0];
            nodes.push(p);
            nodes.len() - 1
        })
    };
    let mut triangles = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            // y decreases with j: (i, j+1) is below (i, j). Counter-clockwise in (x, y):
            let (a, b, c, d) = (vid(i, j + 1), vid(i + 1, j + 1), vid(i + 1, j), vid(i, j));
            for [p, q, r] in [[a, b, c], [a, c, d]] {
                let m0 = mid(p, q, &mut nodes);
                let m1 = mid(q, r, &mut nodes);
                let m2 = mid(r, p, &mut nodes);
                triangles.push([p, q, r, m0, m1, m2]);
            }
        }
    }
    // boundary edges, domain on the left
    let mut boundary_edges = Vec::new();
    let find = |triangles: &Vec<[usize; 6]>, a: usize, b: usize| -> (usize, usize) {
        for (t, tri) in triangles.iter().enumerate() {
            for (k, [s, e, _]) in [[0, 1, 3], [1, 2, 4], [2, 0, 5]].iter().enumerate() {
                if tri[*s] == a && tri[*e] == b {
                    return (t, k);
                }
            }
        }
        panic!("edge {a}-{b} not found");
    };
    let mut push = |a: usize, b: usize, name: usize, triangles: &Vec<[usize; 6]>| {
        let (t, k) = find(triangles, a, b);
        let m = triangles[t][[3, 4, 5][k]];
        boundary_edges.push(BoundaryEdge {
            nodes: [a, b, m],
            name,
            triangle: t,
            local_edge: k,
        });
    };
    for i in 0..nx {
        push(vid(i + 1, 0), vid(i, 0), 1, &triangles); // top, right to left
        push(vid(i, ny), vid(i + 1, ny), 0, &triangles); // bottom
    }
    for j in 0..ny {
        push(vid(nx, j + 1), vid(nx, j), 0, &triangles); // right side, upwards
        push(vid(0, j), vid(0, j + 1), 0, &triangles); // left side, downwards
    }
    Mesh {
        nodes,
        num_vertices,
        triangles,
        boundary_edges,
        boundary_names: vec!["default".into(), "rotation".into(), "contact_head".into()],
        region_name: "pendulum".into(),
        order: 2,
    }
}

/// How [`check_derivatives`] probes a term.
pub struct Probe<'a> {
    /// The degrees of freedom whose gradient entries and Hessian columns are checked.
    pub dofs: &'a [usize],
    /// The finite-difference step \[m\].
    pub step: f64,
    /// Relative tolerance of the gradient (of its largest entry) and of the Hessian columns.
    pub tolerance: f64,
    /// The Hessian's scale for its tolerance \[N/m\]; `None`: each column's largest entry.
    pub hessian_scale: Option<f64>,
}

/// Checks a term's fused energy against `energy`, its gradient against central differences of the
/// energy, and its Hessian columns (through the pattern) against central differences of the
/// gradient, at `u`, time 0 and θ = 0; the errors of central differences are O(step²).
pub fn check_derivatives(
    term: &dyn pendulum_fem::terms::Term,
    pattern: &pendulum_fem::assembly::Pattern,
    u: &[f64],
    probe: &Probe,
    label: &str,
) {
    let n = u.len();
    // the state by itself at t = 0, θ = 0 (the branch of angle-valued terms), no held input
    let cx = pendulum_fem::terms::StepContext::at(u, 0.0, 0.0, None);
    let (mut g, mut k) = (vec![0.0; n], vec![0.0; pattern.nnz()]);
    let e = term.assemble(u, &cx, pattern, &mut g, &mut k);
    assert!(
        (e - term.energy(u, &cx)).abs() <= 1e-12 * e.abs().max(1e-12),
        "{label}: fused energy differs"
    );
    let g_scale = g.iter().map(|v| v.abs()).max_of();
    let h = probe.step;
    for &dof in probe.dofs {
        let (mut up, mut um) = (u.to_vec(), u.to_vec());
        up[dof] += h;
        um[dof] -= h;
        let fd = (term.energy(&up, &cx) - term.energy(&um, &cx)) / (2.0 * h);
        assert!(
            (fd - g[dof]).abs() <= probe.tolerance * g_scale + 1e-9,
            "{label}: g[{dof}] = {} vs fd {fd}",
            g[dof]
        );
        let (mut gp, mut gm) = (vec![0.0; n], vec![0.0; n]);
        term.add_gradient(&up, &cx, &mut gp);
        term.add_gradient(&um, &cx, &mut gm);
        let (mut col, mut unit) = (vec![0.0; n], vec![0.0; n]);
        unit[dof] = 1.0;
        pattern.sym_matvec(&k, &unit, &mut col);
        let k_scale = probe
            .hessian_scale
            .unwrap_or_else(|| col.iter().map(|v| v.abs()).max_of().max(1e-300));
        for r in 0..n {
            let fd = (gp[r] - gm[r]) / (2.0 * h);
            assert!(
                (fd - col[r]).abs() <= probe.tolerance * k_scale,
                "{label}: K[{r}][{dof}] = {} vs fd {fd}",
                col[r]
            );
        }
    }
}
