//! The wall's contact term at term level, rigid and with the deformable block's face: its energy,
//! gradient and Hessian against finite differences, the discrete-gradient identity through the
//! moment of impact, and nothing when apart. (The runs are in `tests/wall.rs`.)

use crate::common;
use common::Extremes;

use pendulum_fem::assembly::Pattern;
use pendulum_fem::terms::{dense_block, StepContext, StepStart, Term, WallContact};
use pendulum_fem::{mesh, Config, Mesh};

fn tutorial_mesh() -> Mesh {
    mesh::generate(&Config::default()).expect("tutorial mesh")
}

/// The head pushed by `dx` in x, plus a wiggle.
fn shifted(mesh: &Mesh, dx: f64, seed: f64) -> Vec<f64> {
    let mut u = common::wiggle(2 * mesh.num_nodes(), 2e-6, seed);
    for n in 0..mesh.num_nodes() {
        u[2 * n] += dx;
    }
    u
}

/// The wall 0.1 mm inside the hanging head's leftmost point (x = −0.06 m).
fn wall(mesh: &Mesh, stiffness: f64) -> WallContact {
    WallContact::new(mesh, "contact_head", -0.0599, stiffness, 0.01, 8).unwrap()
}

#[test]
fn apart_the_wall_has_no_energy_no_force_and_no_stiffness() {
    let mesh = tutorial_mesh();
    let term = WallContact::new(&mesh, "contact_head", -0.07, 2e10, 0.01, 8).unwrap();
    let u = shifted(&mesh, 0.0, 1.0);
    let pattern = Pattern::new(&mesh, &[]);
    let (mut g, mut k) = (vec![0.0; u.len()], vec![0.0; pattern.nnz()]);
    let e = term.assemble(&u, &StepContext::at(&u, 0.0, 0.0, None), &pattern, &mut g, &mut k);
    assert_eq!(e, 0.0);
    assert!(g.iter().chain(&k).all(|x| *x == 0.0));
    assert!(
        (term.smallest_gap(&u) - 0.01).abs() < 1e-5,
        "gap {}",
        term.smallest_gap(&u)
    );
}

#[test]
fn the_contact_gradient_and_hessian_match_finite_differences() {
    let mesh = tutorial_mesh();
    let term = wall(&mesh, 2e10);
    let u = shifted(&mesh, -2e-5, 2.0);
    let pattern = Pattern::new(&mesh, &[]);
    let n = u.len();
    let (mut g, mut k) = (vec![0.0; n], vec![0.0; pattern.nnz()]);
    term.assemble(&u, &StepContext::at(&u, 0.0, 0.0, None), &pattern, &mut g, &mut k);
    let scale = g.iter().map(|v| v.abs()).max_of();
    assert!(scale > 0.0, "the head is pressed into the wall");
    // the force resultant equals the normal force the term reports
    let fx: f64 = g.iter().step_by(2).sum();
    assert!((fx + term.normal_force(&u)).abs() <= 1e-12 * scale * n as f64);
    // a step of 1 nm, far below the penetrations (≥ 1e-4 m), so that no point switches on or off:
    // central differences of a piecewise quadratic are exact up to the energies' rounding
    let dofs: Vec<usize> = mesh
        .nodes_on("contact_head")
        .iter()
        .flat_map(|&a| [2 * a, 2 * a + 1])
        .collect();
    let probe = common::Probe {
        dofs: &dofs,
        step: 1e-9,
        tolerance: 1e-5,
        hessian_scale: None,
    };
    common::check_derivatives(&term, &pattern, &u, &probe, "rigid wall");
}

#[test]
fn through_an_impact_the_discrete_work_is_the_change_of_contact_energy() {
    let mesh = tutorial_mesh();
    for stiffness in [2e10, 1e14] {
        let term = wall(&mesh, stiffness);
        // apart → pressed, pressed → deeper, pressed → apart, apart → apart
        for (k, (d0, d1)) in [(1e-4, -3e-5), (-1e-5, -4e-5), (-2e-5, 2e-4), (1e-3, 2e-4)]
            .into_iter()
            .enumerate()
        {
            let (u0, u1) = (shifted(&mesh, d0, k as f64), shifted(&mesh, d1, 10.0 + k as f64));
            let start = StepStart {
                u: &u0,
                data: &[],
                dissipation: 0.0,
            };
            let mut g = vec![0.0; u0.len()];
            let cx = StepContext {
                t: 0.01,
                t0: 0.0,
                dt: 0.01,
                u0: &u0,
                theta0: 0.0,
                torque: None,
            };
            term.add_discrete_gradient(&start, &u1, &cx, 1.0, &mut g);
            let work: f64 = g.iter().zip(u1.iter().zip(&u0)).map(|(f, (a, b))| f * (a - b)).sum();
            let change = term.energy(&u1, &StepContext::at(&u1, 0.01, 0.0, None))
                - term.energy(&u0, &StepContext::at(&u0, 0.0, 0.0, None));
            let scale = term
                .energy(&u1, &StepContext::at(&u1, 0.0, 0.0, None))
                .max(term.energy(&u0, &StepContext::at(&u0, 0.0, 0.0, None)))
                .max(1e-30);
            assert!(
                (work - change).abs() <= 1e-12 * scale,
                "k = {stiffness}, step {k}: work {work:e} vs change {change:e}"
            );
        }
    }
}

/// The model of the contact tutorial's deformable wall: its mesh (pendulum, then block), the
/// contact term, and the first node of the block.
fn deformable() -> (Mesh, WallContact, usize) {
    let mut cfg = Config::default();
    cfg.wall.kind = pendulum_fem::config::WallKind::Deformable;
    let mesh = mesh::generate(&cfg).unwrap();
    let model = pendulum_fem::Model::new(&cfg, mesh).unwrap();
    let first = model.bodies[1].nodes.start;
    (model.mesh.clone(), model.wall.clone().expect("a wall"), first)
}

/// The head (nodes before `first`) pushed by `dx` and the block's nodes moved by a wiggle of
/// `amp` (its face bent), plus a small wiggle everywhere.
fn pressed(mesh: &Mesh, first: usize, dx: f64, amp: f64, seed: f64) -> Vec<f64> {
    let mut u = common::wiggle(2 * mesh.num_nodes(), 2e-6, seed);
    let bend = common::wiggle(2 * mesh.num_nodes(), amp, seed + 7.0);
    for n in 0..mesh.num_nodes() {
        if n < first {
            u[2 * n] += dx;
        } else {
            u[2 * n] += bend[2 * n];
            u[2 * n + 1] += bend[2 * n + 1];
        }
    }
    u
}

#[test]
fn the_deformable_face_contact_gradient_matches_finite_differences() {
    let (mesh, term, first) = deformable();
    let u = pressed(&mesh, first, -5e-5, 1e-6, 3.0);
    let pattern = Pattern::new(&mesh, &term.hessian_entries());
    let cx = StepContext::at(&u, 0.0, 0.0, None);
    let mut g = vec![0.0; u.len()];
    term.add_gradient(&u, &cx, &mut g);
    let scale = g.iter().map(|v| v.abs()).max_of();
    assert!(scale > 0.0, "the head is pressed into the face");
    // the forces on head and face balance in x (the face's slope is ~1e-4: y forces are small)
    let (fx_head, fx_face): (f64, f64) = (
        g[..2 * first].iter().step_by(2).sum(),
        g[2 * first..].iter().step_by(2).sum(),
    );
    assert!(
        (fx_head + fx_face).abs() < 1e-6 * fx_head.abs(),
        "{fx_head} vs {fx_face}"
    );
    // every degree of freedom that carries a force, head and face, against central differences
    // of the energy with a 1 nm step (no point changes contact state or face segment)
    // the Jacobian couples head and face nodes (entries listed by the term, in the pattern)
    let mut k = vec![0.0; pattern.nnz()];
    term.add_hessian(&u, &cx, &pattern, &mut k);
    let couples = term
        .hessian_entries()
        .iter()
        .any(|&(r, c)| r < 2 * first && c >= 2 * first && k[pattern.position(r, c).expect("listed")] != 0.0);
    assert!(couples, "no head–face stiffness");
    let dofs: Vec<usize> = (0..u.len()).filter(|&i| g[i] != 0.0).collect();
    assert!(dofs.iter().any(|&d| d >= 2 * first) && dofs.iter().any(|&d| d < 2 * first));
    for &d in &dofs {
        let (mut up, mut um) = (u.clone(), u.clone());
        up[d] += 1e-9;
        um[d] -= 1e-9;
        let fd = (term.energy(&up, &cx) - term.energy(&um, &cx)) / 2e-9;
        // the energy is ~1e-2 J of terms k w g²/2: its rounding over 2 nm gives ~1e-6 of the scale
        assert!((fd - g[d]).abs() <= 1e-5 * scale, "dof {d}: {} vs fd {fd}", g[d]);
    }
}

#[test]
fn through_an_impact_on_the_deformable_face_the_discrete_work_is_the_change_of_contact_energy() {
    let (mesh, term, first) = deformable();
    for (k, (d0, d1)) in [(1e-4, -3e-5), (-1e-5, -4e-5), (-2e-5, 2e-4)].into_iter().enumerate() {
        let u0 = pressed(&mesh, first, d0, 1e-6, k as f64);
        let u1 = pressed(&mesh, first, d1, 1e-6, 10.0 + k as f64);
        let start = StepStart {
            u: &u0,
            data: &[],
            dissipation: 0.0,
        };
        let cx = StepContext {
            t: 0.01,
            t0: 0.0,
            dt: 0.01,
            u0: &u0,
            theta0: 0.0,
            torque: None,
        };
        let mut g = vec![0.0; u0.len()];
        term.add_discrete_gradient(&start, &u1, &cx, 1.0, &mut g);
        let work: f64 = g.iter().zip(u1.iter().zip(&u0)).map(|(f, (a, b))| f * (a - b)).sum();
        let e = |u: &[f64]| term.energy(u, &StepContext::at(u, 0.0, 0.0, None));
        let change = e(&u1) - e(&u0);
        let scale = e(&u1).max(e(&u0));
        // exact whatever segments of the (bent) face a point crosses: the rounding of a sum of
        // ~1000 terms of the energy's size
        assert!(
            (work - change).abs() <= 1e-12 * scale,
            "step {k}: work {work:e} vs change {change:e}"
        );
    }
}

/// The head (nodes before `first`) moved by `(dx, dy)`, the block bent by a wiggle of 1 µm.
fn moved(mesh: &Mesh, first: usize, dx: f64, dy: f64, seed: f64) -> Vec<f64> {
    let mut u = pressed(mesh, first, dx, 1e-6, seed);
    for n in 0..first {
        u[2 * n + 1] += dy;
    }
    u
}

/// The tutorial face's top end `y` \[m\] and the head's leftmost arc node (its first contact).
fn face_top_and_leftmost(mesh: &Mesh) -> (f64, usize) {
    let cfg = Config::default();
    let leftmost = mesh
        .nodes_on("contact_head")
        .into_iter()
        .min_by(|&a, &b| mesh.nodes[a][0].total_cmp(&mesh.nodes[b][0]))
        .unwrap();
    (cfg.wall.center_y + 0.5 * cfg.wall.height, leftmost)
}

/// The head pressed 30 µm into the face with its leftmost arc node `dy` past the face's top end
/// (the block bent by a wiggle of 1 µm).
fn lifted_past_the_top(mesh: &Mesh, first: usize, dy: f64) -> Vec<f64> {
    let (top, leftmost) = face_top_and_leftmost(mesh);
    moved(mesh, first, -3e-5, top - mesh.nodes[leftmost][1] + dy, 1.0)
}

#[test]
fn a_point_that_crosses_the_end_of_the_face_keeps_the_discrete_work_equal_to_the_change_of_energy() {
    let (mesh, term, first) = deformable();
    // the head's leftmost node (its first contact) lifted from 0.5 mm below the face's top end to
    // 1 mm above it (the taper is one face element, 1.5 mm), pressed 30 µm into the face
    let (top, leftmost) = face_top_and_leftmost(&mesh);
    let y = mesh.nodes[leftmost][1];
    for (k, (y0, y1)) in [
        (top - 5e-4, top + 1e-3),
        (top + 1e-3, top - 5e-4),
        (top - 3e-3, top + 3e-3),
    ]
    .into_iter()
    .enumerate()
    {
        let u0 = moved(&mesh, first, -3e-5, y0 - y, k as f64);
        let u1 = moved(&mesh, first, -3e-5, y1 - y, 10.0 + k as f64);
        let start = StepStart {
            u: &u0,
            data: &[],
            dissipation: 0.0,
        };
        let cx = StepContext {
            t: 0.01,
            t0: 0.0,
            dt: 0.01,
            u0: &u0,
            theta0: 0.0,
            torque: None,
        };
        let mut g = vec![0.0; u0.len()];
        term.add_discrete_gradient(&start, &u1, &cx, 1.0, &mut g);
        let work: f64 = g.iter().zip(u1.iter().zip(&u0)).map(|(f, (a, b))| f * (a - b)).sum();
        let e = |u: &[f64]| term.energy(u, &StepContext::at(u, 0.0, 0.0, None));
        let (e0, e1) = (e(&u0), e(&u1));
        println!("crossing {k}: E0 {e0:e} J, E1 {e1:e} J, work {work:e} J");
        // the points leave (or enter) the face at the same depth: the energy changes by much of itself
        assert!((e1 - e0).abs() > 0.1 * e0.max(e1), "step {k}: E0 {e0:e}, E1 {e1:e}");
        // exact up to the rounding of a sum of ~1000 terms of the energy's size
        assert!(
            (work - (e1 - e0)).abs() <= 1e-12 * e0.max(e1),
            "step {k}: work {work:e} vs change {:e}",
            e1 - e0
        );
    }
}

#[test]
fn the_energy_fades_out_smoothly_past_the_end_of_the_face() {
    let (mesh, term, first) = deformable();
    let e = |dy: f64| {
        let u = lifted_past_the_top(&mesh, first, dy);
        term.energy(&u, &StepContext::at(&u, 0.0, 0.0, None))
    };
    // across the end in steps of 10 µm: no jump (a cut at the end would drop a point's whole
    // energy in one step, about a tenth of the total: ~10 Gauss points share the 30 µm contact)
    let values: Vec<f64> = (-300..=600).map(|i| e(1e-5 * i as f64)).collect();
    let (inside, beyond) = (values[0], *values.last().unwrap());
    println!("energy 3 mm inside the end {inside:e} J, 6 mm beyond {beyond:e} J");
    assert!(
        inside > 0.0 && beyond < 1e-3 * inside,
        "it fades out: {inside:e} → {beyond:e}"
    );
    let largest = values.windows(2).map(|w| (w[1] - w[0]).abs()).max_of();
    // the smooth taper over ~1.5 mm changes the energy by at most ~(10 µm / 1.5 mm)·1.5 of itself per step
    assert!(
        largest < 2e-2 * inside,
        "largest change over 10 µm: {largest:e} J of {inside:e} J"
    );
}

#[test]
fn the_deformable_faces_hessian_pattern_holds_every_entry_it_writes_and_a_contact_outside_it_is_named() {
    let (mesh, term, first) = deformable();
    let model_pattern = Pattern::new(&mesh, &term.hessian_entries());
    // every degree of freedom of the head's arc and of the block's face, all coupled
    let mut dofs: Vec<usize> = mesh
        .nodes_on("contact_head")
        .into_iter()
        .chain(mesh.nodes_on("contact_wall"))
        .flat_map(|n| [2 * n, 2 * n + 1])
        .collect();
    dofs.sort_unstable();
    let dense = Pattern::new(&mesh, &dense_block(&dofs));
    // pressed at the tutorial's contact, and turned about the pivot by ±5° into the face
    let mut states = vec![pressed(&mesh, first, -5e-5, 1e-6, 3.0)];
    for deg in [-5.0f64, 5.0] {
        let (s, c) = deg.to_radians().sin_cos();
        let mut u = common::wiggle(2 * mesh.num_nodes(), 1e-6, deg);
        let leftmost = (0..first).map(|n| c * mesh.nodes[n][0] - s * mesh.nodes[n][1]).min_of();
        let shift = -0.06 - leftmost - 4e-5;
        for n in 0..first {
            let p = mesh.nodes[n];
            u[2 * n] += c * p[0] - s * p[1] - p[0] + shift;
            u[2 * n + 1] += s * p[0] + c * p[1] - p[1];
        }
        states.push(u);
    }
    for (k, u) in states.iter().enumerate() {
        let cx = StepContext::at(u, 0.0, 0.0, None);
        let (mut km, mut kd) = (vec![0.0; model_pattern.nnz()], vec![0.0; dense.nnz()]);
        term.add_hessian(u, &cx, &model_pattern, &mut km);
        term.add_hessian(u, &cx, &dense, &mut kd);
        let mut head_face = 0;
        for (i, &r) in dofs.iter().enumerate() {
            for &c in &dofs[i..] {
                let value = kd[dense.position(r, c).unwrap()];
                if value == 0.0 {
                    continue;
                }
                head_face += usize::from(r < 2 * first && c >= 2 * first);
                let kept = model_pattern.position(r, c).map(|p| km[p]);
                // the same sum in the same order: bit for bit
                assert_eq!(kept, Some(value), "state {k}: entry ({r}, {c}) dropped");
            }
        }
        assert!(head_face > 0, "state {k}: the head presses the face");
        assert_eq!(term.uncoupled_contact(u), None, "state {k}");
    }
    // the head lifted by 8 cm and pressed into the face: no turn about the pivot puts it there
    let u = moved(&mesh, first, -3e-5, 0.08, 1.0);
    let message = term.uncoupled_contact(&u).expect("a contact outside the pattern");
    println!("{message}");
    assert!(
        message.contains("sparsity pattern") && message.contains("face segment"),
        "{message}"
    );
}

#[test]
fn past_the_end_of_the_face_the_reported_penetration_fades_with_the_energy() {
    let (mesh, term, first) = deformable();
    // the head pressed 30 µm into the face, its leftmost node lifted to `dy` past the top end
    let depth = |dy: f64| -term.smallest_gap(&lifted_past_the_top(&mesh, first, dy));
    let on_face = depth(-3e-3);
    let lifted: Vec<f64> = (0..=30).map(|i| depth(1e-4 * i as f64)).collect();
    println!("on the face {on_face:e} m; lifted by 0.1 mm steps: {lifted:?}");
    assert!((2.5e-5..3.5e-5).contains(&on_face), "{on_face}");
    // a point in the taper (one face element, 1.5 mm, past the end) penetrates by g √s(η), the
    // depth that stores its energy on the face: the reported penetration falls as the contact
    // leaves the face. Measured against the face's line continued past the block, where there
    // is no block, it grew instead (3.13e-5 to 3.17e-5 m over the first 0.6 mm)
    assert!(
        lifted[5..].windows(2).all(|w| w[1] <= w[0]),
        "it falls once the contact leaves the face: {lifted:?}"
    );
    assert!(
        lifted[25] < 0.2 * on_face,
        "2.5 mm past the end: {:e} of {on_face:e}",
        lifted[25]
    );
    // none once every point is past the taper
    assert!(depth(5e-3) <= 0.0, "{}", depth(5e-3));
}
