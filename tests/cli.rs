//! The command line: errors name the key or file and what is allowed, exit non-zero, and never
//! damage results already written; `init` writes a configuration that reads back as the defaults.

use std::path::PathBuf;
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pendulum-fem"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pendulum-fem-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn unknown_keys_are_rejected_with_their_name() {
    let dir = scratch("unknown");
    let cfg = dir.join("bad.toml");
    std::fs::write(&cfg, "[mesh]\nmax_sise = 0.01\n").unwrap();
    let o = bin()
        .args(["run", "--config"])
        .arg(&cfg)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(stderr(&o).contains("max_sise"), "{}", stderr(&o));
    assert!(
        !dir.join("out").join("results.csv").exists(),
        "nothing is computed for a bad configuration"
    );
}

#[test]
fn out_of_range_values_name_the_key_and_the_allowed_range() {
    for (set, key) in [
        ("mesh.max_size=-0.1", "mesh.max_size"),
        ("material.poisson_ratio=0.6", "material.poisson_ratio"),
        ("time.dt=0", "time.dt"),
        ("geometry.hole_radius=0.07", "geometry.hole_radius"),
        ("mesh.order=3", "mesh.order"),
    ] {
        let o = bin().args(["run", "--set", set]).output().unwrap();
        assert!(!o.status.success(), "{set} accepted");
        let msg = stderr(&o);
        assert!(msg.contains(key) && msg.contains("allowed"), "{set}: {msg}");
    }
}

#[test]
fn a_failing_step_names_step_time_and_residual_and_keeps_the_rows_written() {
    let dir = scratch("fail");
    let out = dir.join("out");
    // an energy tolerance no update can reach, one iteration, no cut-back: step 1 must fail
    // (undeformed start, so the initial equilibrium solve is not involved)
    let o = bin()
        .args([
            "run",
            "--quiet",
            "--set",
            "solver.max_iterations=1",
            "--set",
            "solver.max_cutbacks=0",
        ])
        .args([
            "--set",
            "solver.tolerance=1e-300",
            "--set",
            "initial.elastic=undeformed",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!o.status.success());
    let msg = stderr(&o);
    assert!(
        msg.contains("time step 1") && msg.contains("t = 0.000000 s") && msg.contains("residual"),
        "{msg}"
    );
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 2, "header and the initial row: {csv}");
    assert!(lines[0].starts_with("time_s,theta_rad,omega_rad_s,alpha_rad_s2,kinetic_J,strain_J,gravity_J,total_J,hinge_fx_N,hinge_fy_N,von_mises_max_Pa,newton_iterations"));
    assert!(lines[1].starts_with("0,"));
}

#[test]
fn init_writes_a_commented_configuration_that_reads_back_as_the_defaults() {
    let dir = scratch("init");
    let file = dir.join("p.toml");
    let o = bin().arg("init").arg(&file).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("# m/s^2") || text.contains("m/s^2"));
    assert_eq!(
        pendulum_fem::Config::load(Some(&file), &[]).unwrap(),
        pendulum_fem::Config::default()
    );
    // a second init refuses to overwrite
    let o = bin().arg("init").arg(&file).output().unwrap();
    assert!(!o.status.success() && stderr(&o).contains("--force"));
}

#[test]
fn help_lists_every_subcommand() {
    let o = bin().arg("--help").output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    for sub in ["run", "mesh", "init", "bench"] {
        assert!(text.contains(sub), "--help lacks {sub}: {text}");
    }
}
