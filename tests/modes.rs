//! Modal analysis (`pendulum_fem::modal`, `pendulum-fem modes`): the natural frequencies of the
//! pinned pendulum about the undeformed state against an independent NGSolve computation
//! (`tests/data/ngsolve_modes.json`, made by `scripts/ngsolve/pendulum_modes.py`: its own Netgen
//! mesh, P4 elements refined twice, SciPy's ARPACK shift-invert), their convergence under mesh
//! refinement, the eigenpairs' checks and the command line.

use crate::common;
use common::Extremes;

use pendulum_fem::commands::modes::compute;
use pendulum_fem::modal;
use pendulum_fem::{Config, Model};

/// Elastic modes compared with the reference.
const COMPARED: usize = 8;

fn config(sets: &[&str]) -> Config {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Config::load(None, &sets).unwrap()
}

/// The reference's elastic frequencies \[Hz\].
fn ngsolve_hz() -> Vec<f64> {
    let text = std::fs::read_to_string(common::root().join("tests/data/ngsolve_modes.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["reference"]["elastic_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// The first `n` elastic frequencies of the pendulum of `cfg` \[Hz\] (the rigid mode dropped).
fn elastic_hz(cfg: &Config, n: usize) -> Vec<f64> {
    let c = compute(cfg, n + 1).unwrap();
    let scale = modal::eigenvalue_scale(&c.model.pattern, &c.stiffness, &c.model.mass);
    assert_eq!(c.modes.rigid_count(scale), 1, "{:?}", &c.modes.eigenvalues[..3]);
    c.modes.frequencies_hz()[1..].to_vec()
}

/// Tolerance: the reference's own discretisation error is below 5e-5 (its change from the
/// previous refinement, stored with it); our default mesh (P2 triangles of the tutorial's sizes)
/// lies above it by the excess of a coarser P2 discretisation over the converged value (the
/// stiffness of a conforming discretisation is an upper bound), a few tenths of a percent. 0.5 %
/// leaves room for the mesher's rounding, not for a wrong operator: a wrong Poisson ratio or plane
/// strain moves the frequencies by 2 % to 10 %.
#[test]
fn the_first_eight_elastic_frequencies_of_the_default_mesh_are_within_half_a_percent_of_ngsolve() {
    let ours = elastic_hz(&config(&[]), COMPARED);
    let reference = ngsolve_hz();
    for (k, (a, b)) in ours.iter().zip(&reference).enumerate() {
        let rel = (a - b) / b;
        println!("mode {}: {a:.3} Hz, NGSolve {b:.3} Hz, {:+.3} %", k + 1, 100.0 * rel);
        assert!(
            rel.abs() < 5e-3,
            "mode {}: {a} Hz vs NGSolve {b} Hz ({:+.3} %)",
            k + 1,
            100.0 * rel
        );
        // a conforming discretisation of the same operator lies above the converged value
        assert!(rel > -5e-5, "mode {}: {a} Hz below the converged {b} Hz", k + 1);
    }
}

/// Refining the mesh (`mesh.refine` 1, 2, 4) moves every frequency towards the reference and by
/// less at every level. The distances to the reference shrink monotonically; the reference is
/// converged to 5e-5, so distances are only compared while above 1e-4.
#[test]
fn the_frequencies_converge_towards_ngsolve_under_mesh_refinement() {
    let reference = ngsolve_hz();
    let levels = ["1", "2", "4"];
    let table: Vec<Vec<f64>> = levels
        .iter()
        .map(|r| elastic_hz(&config(&[&format!("mesh.refine={r}")]), COMPARED))
        .collect();
    for k in 0..COMPARED {
        let row: Vec<String> = table.iter().map(|t| format!("{:.3}", t[k])).collect();
        println!("mode {}: {} | NGSolve {:.3}", k + 1, row.join(" "), reference[k]);
        let err: Vec<f64> = table.iter().map(|t| (t[k] - reference[k]) / reference[k]).collect();
        for w in err.windows(2) {
            if w[0] > 1e-4 {
                assert!(w[1] < w[0], "mode {}: relative errors {err:?} do not shrink", k + 1);
            }
        }
        let steps: Vec<f64> = table.windows(2).map(|w| (w[1][k] - w[0][k]).abs()).collect();
        assert!(steps[1] < steps[0], "mode {}: changes {steps:?} do not shrink", k + 1);
        assert!(err[2].abs() < 1e-3, "mode {}: refine 4 still {:.3e} off", k + 1, err[2]);
    }
}

/// The checks of the eigensolver, recomputed here: the backward error
/// `‖Kφ − ω²Mφ + Cᵀμ‖ / ((‖K‖ + ω²‖M‖)‖φ‖)` below 1e-12 (the Lanczos tolerance is 1e-11 on the
/// shift-inverted operator), `M`-orthonormality to
/// 1e-10 (full reorthogonalisation keeps it at rounding level), the hinge rows to 1e-12 of
/// `‖C‖‖φ‖` (the constraints are eliminated exactly, up to rounding), and the rigid mode is the
/// rotation about the pivot.
#[test]
fn the_eigenpairs_have_small_residuals_are_mass_orthonormal_and_keep_the_hinge() {
    let cfg = config(&[]);
    let model = Model::new(&cfg, pendulum_fem::mesh::generate(&cfg).unwrap()).unwrap();
    let k = modal::stiffness_at_rest(&model);
    let c = model.hinge.dense_rows(model.pattern.n).to_vec();
    let shift = modal::rest_shift(&model);
    let modes = modal::constrained_modes(&model.pattern, &k, &model.mass, &c, 21, shift).unwrap();
    assert_eq!(modes.eigenvalues.len(), 21);
    assert!(modes.eigenvalues.windows(2).all(|w| w[0] <= w[1]), "ascending");
    let [residual, orthonormality, hinge] = modal::verify(&model.pattern, &k, &model.mass, &c, &modes);
    println!("residual {residual:.2e}, orthonormality {orthonormality:.2e}, hinge {hinge:.2e}");
    assert!(residual < 1e-12, "{residual}");
    assert!(orthonormality < 1e-10, "{orthonormality}");
    assert!(hinge < 1e-12, "{hinge}");
    // and the hinge's mean displacement of every shape, against the shape's largest nodal one
    for phi in &modes.shapes {
        let mean = model.hinge.value(phi);
        let largest = phi.iter().map(|v| v.abs()).max_of();
        assert!(mean[0].hypot(mean[1]) < 1e-12 * largest, "{mean:?} of {largest}");
    }
    // mode 0: ω² at rounding level and the shape a rotation (−y, x) about the pivot
    let rigid = &modes.shapes[0];
    let dot = |a: &[f64], b: &[f64]| -> f64 { a.iter().zip(b).map(|(x, y)| x * y).sum() };
    let rotation: Vec<f64> = model.mesh.nodes.iter().flat_map(|p| [-p[1], p[0]]).collect();
    let cos = dot(rigid, &rotation).abs() / (dot(rigid, rigid) * dot(&rotation, &rotation)).sqrt();
    assert!(cos > 1.0 - 1e-9, "rigid mode vs rotation: cos {cos}");
    let scale = modal::eigenvalue_scale(&model.pattern, &k, &model.mass);
    assert!(modes.eigenvalues[0].abs() < 1e-12 * scale, "{}", modes.eigenvalues[0]);
    // a shift above the lowest eigenvalue is refused by name
    let err = modal::constrained_modes(&model.pattern, &k, &model.mass, &c, 4, 1e9).unwrap_err();
    assert!(err.to_string().contains("not positive definite"), "{err}");
}

/// `constrained_static` solves `K x = f` on `ker C` where `K` is singular on the whole space:
/// the pendulum with the hinge and a third row holding the rotation, checked by the equations
/// themselves (`K x + Cᵀμ = f` to 1e-9 of the 1 N load, the refinement's acceptance; `C x = 0`
/// to 1e-10 of `‖C‖‖x‖`). With the hinge alone the rotation is free and the solve is refused.
#[test]
fn constrained_static_solves_the_held_pendulum_and_refuses_a_free_rotation() {
    let cfg = config(&[]);
    let model = Model::new(&cfg, pendulum_fem::mesh::generate(&cfg).unwrap()).unwrap();
    let k = modal::stiffness_at_rest(&model);
    let n = model.pattern.n;
    let mut c = model.hinge.dense_rows(n).to_vec();
    // a unit tip load along x at the lowest node
    let tip = (0..model.mesh.num_nodes())
        .min_by(|&a, &b| model.mesh.nodes[a][1].total_cmp(&model.mesh.nodes[b][1]))
        .unwrap();
    let mut f = vec![0.0; n];
    f[2 * tip] = 1.0;
    let err = modal::constrained_static(&model.pattern, &k, &c, std::slice::from_ref(&f)).unwrap_err();
    assert!(err.to_string().contains("not positive definite on ker C"), "{err}");
    // hold the rotation: the mass-weighted rotation functional Σ (−y, x)·u
    let rotation: Vec<f64> = model.mesh.nodes.iter().flat_map(|p| [-p[1], p[0]]).collect();
    let mut m_rot = vec![0.0; n];
    model.mass.apply(&rotation, &mut m_rot);
    c.push(m_rot);
    let x = modal::constrained_static(&model.pattern, &k, &c, &[f.clone()])
        .unwrap()
        .remove(0);
    for row in &c {
        let s: f64 = row.iter().zip(&x).map(|(a, b)| a * b).sum();
        let scale: f64 = row.iter().map(|a| a * a).sum::<f64>().sqrt() * x.iter().map(|a| a * a).sum::<f64>().sqrt();
        assert!(s.abs() < 1e-10 * scale, "C x = {s}");
    }
    // the tip moves along the load, by a steel plate's compliance (µm per kN order)
    assert!(x[2 * tip] > 0.0 && x[2 * tip] < 1e-6, "{}", x[2 * tip]);
    // the equations: K x + Cᵀμ = f for some μ, i.e. f − K x in the span of the rows
    let mut kx = vec![0.0; n];
    model.pattern.sym_matvec(&k, &x, &mut kx);
    let r: Vec<f64> = f.iter().zip(&kx).map(|(a, b)| a - b).collect();
    let residual = least_squares_residual(&c, &r);
    assert!(residual < 1e-9, "relative residual {residual}");
}

/// `min_μ ‖r − Cᵀμ‖ / ‖r‖`… relative to 1 N (the load): Gram–Schmidt over the rows.
fn least_squares_residual(rows: &[Vec<f64>], r: &[f64]) -> f64 {
    let dot = |a: &[f64], b: &[f64]| -> f64 { a.iter().zip(b).map(|(x, y)| x * y).sum() };
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for row in rows {
        let mut v = row.clone();
        for b in &basis {
            let c = dot(&v, b);
            v.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
        }
        let norm = dot(&v, &v).sqrt();
        basis.push(v.iter().map(|x| x / norm).collect());
    }
    let mut res = r.to_vec();
    for b in &basis {
        let c = dot(&res, b);
        res.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
    }
    dot(&res, &res).sqrt()
}

/// The real binary writes `modes.json` (the frequencies of the library, to 1e-9: the same
/// computation, printed with 17 digits), `modes.pvd` with one `.vtu` per mode and `modes.png`.
#[test]
fn the_modes_command_writes_json_pvd_and_png_with_the_same_frequencies() {
    let dir = common::scratch("cli");
    let out = common::bin()
        .args(["modes", "--n", "8", "-o"])
        .arg(&dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("f [Hz]") && stdout.contains("rigid rotation"),
        "{stdout}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("modes.json")).unwrap()).unwrap();
    let rows = json["modes"].as_array().unwrap();
    assert_eq!(rows.len(), 9, "the rigid mode and 8 elastic ones");
    assert_eq!(rows[0]["rigid"], true);
    assert_eq!(rows[0]["frequency_hz"].as_f64().unwrap(), 0.0);
    let library = elastic_hz(&config(&[]), 8);
    for (row, f) in rows[1..].iter().zip(&library) {
        let g = row["frequency_hz"].as_f64().unwrap();
        assert!((g - f).abs() < 1e-9 * f, "{g} vs {f}");
    }
    let pvd = std::fs::read_to_string(dir.join("modes.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 9, "{pvd}");
    for k in 0..9 {
        let vtu = dir.join(format!("modes/mode_{k:02}.vtu"));
        assert!(pvd.contains(&format!("modes/mode_{k:02}.vtu")));
        let head = std::fs::read(&vtu).unwrap();
        assert!(String::from_utf8_lossy(&head[..2000.min(head.len())]).contains("displacement_m"));
    }
    let png = std::fs::read(dir.join("modes.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--n` outside 1..=50 fails with a message naming the option and the allowed range, exit
/// code non-zero, and nothing is written.
#[test]
fn a_bad_mode_count_fails_naming_the_option_and_the_allowed_range() {
    for bad in ["0", "-3", "51"] {
        let dir = common::scratch(&format!("bad{bad}")).join("out");
        let out = common::bin()
            .args(["modes", "--n", bad, "-o"])
            .arg(&dir)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "--n {bad} accepted");
        assert!(
            stderr.contains(&format!("--n {bad}")) && stderr.contains("allowed 1 to 50"),
            "--n {bad}: {stderr}"
        );
        assert!(!dir.exists(), "--n {bad} wrote {}", dir.display());
    }
    let out = common::bin().args(["modes", "--n", "many"]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--n"));
}

/// `modes` picks its folder as `run` does: without `--out` a fresh `output.dir/modes-NNNN` each
/// time; an `--out` that holds anything is refused without `--force`, changing nothing; with
/// `--force` the files of an earlier `modes` there are replaced (a stale mode shape of a longer
/// earlier table goes) and other files are kept.
#[test]
fn modes_writes_a_fresh_folder_or_refuses_a_non_empty_out_without_force_as_run_does() {
    let dir = common::scratch("outdir");
    let modes = |args: &[&str]| {
        common::bin()
            .current_dir(&dir)
            .args(["modes", "--n", "2", "--set", "output.dir=res"])
            .args(args)
            .output()
            .unwrap()
    };
    for k in 1..=2 {
        let o = modes(&[]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let folder = dir.join(format!("res/modes-{k:04}"));
        assert!(folder.join("modes.json").is_file(), "run {k}: no {}", folder.display());
        assert!(
            String::from_utf8_lossy(&o.stdout).contains(&folder.strip_prefix(&dir).unwrap().display().to_string()),
            "the folder is named: {}",
            String::from_utf8_lossy(&o.stdout)
        );
    }
    let mut top: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    top.sort();
    assert_eq!(top, ["res"], "nothing written beside output.dir");

    let out = dir.join("mine");
    std::fs::create_dir_all(out.join("modes")).unwrap();
    std::fs::write(out.join("notes.txt"), "keep me").unwrap();
    std::fs::write(out.join("modes/mode_07.vtu"), "a mode of an earlier, longer table").unwrap();
    let refused = modes(&["--out", "mine"]);
    assert!(!refused.status.success(), "a non-empty --out accepted without --force");
    let msg = String::from_utf8_lossy(&refused.stderr);
    assert!(msg.contains("mine") && msg.contains("--force"), "{msg}");
    assert!(!out.join("modes.json").exists(), "the refusal wrote {}", out.display());
    assert!(out.join("modes/mode_07.vtu").is_file(), "the refusal removed a file");

    let forced = modes(&["--out", "mine", "--force"]);
    assert!(forced.status.success(), "{}", String::from_utf8_lossy(&forced.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("modes.json")).unwrap()).unwrap();
    assert_eq!(
        json["modes"].as_array().unwrap().len(),
        3,
        "the rigid mode and 2 elastic ones"
    );
    assert!(
        !out.join("modes/mode_07.vtu").exists(),
        "a mode shape of the earlier table is left"
    );
    assert!(out.join("modes/mode_02.vtu").is_file());
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).unwrap(), "keep me");
    let _ = std::fs::remove_dir_all(&dir);
}
