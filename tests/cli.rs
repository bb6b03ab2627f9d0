//! The command line: errors name the key or file and what is allowed, exit non-zero, and never
//! damage results already written; `init` writes a configuration that reads back as the defaults.

use crate::common;
use common::Extremes;

use std::process::{Command, Output};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn unknown_keys_are_rejected_with_their_name_line_and_the_nearest_allowed_key() {
    let dir = common::scratch("unknown");
    let cfg = dir.join("bad.toml");
    std::fs::write(&cfg, "[mesh]\nmax_sise = 0.01\n").unwrap();
    let o = common::bin()
        .args(["run", "--config"])
        .arg(&cfg)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("unknown key \"max_sise\" in [mesh] at line 2; did you mean \"max_size\"?"),
        "{}",
        stderr(&o)
    );
    assert!(
        !dir.join("out").join("results.csv").exists(),
        "nothing is computed for a bad configuration"
    );
}

#[test]
fn a_file_with_two_mistakes_reports_both_the_earlier_line_first_and_exits_non_zero() {
    let dir = common::scratch("two-mistakes");
    let cfg = dir.join("two.toml");
    // [time] sorts after [mesh]: the report follows the lines, not the sections' order
    std::fs::write(&cfg, "[time]\nedn = 2.0\n\n[mesh]\nmax_size = -0.1\n").unwrap();
    let o = common::bin()
        .args(["run", "--config"])
        .arg(&cfg)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    let msg = stderr(&o);
    let first = msg.find("unknown key \"edn\" in [time] at line 2; did you mean \"end\"?");
    let second = msg.find("mesh.max_size = -0.1: allowed a finite value > 0 m (at line 5)");
    assert!(
        msg.contains("2 mistakes") && first.is_some() && second.is_some() && first < second,
        "{msg}"
    );
    assert!(!dir.join("out").join("results.csv").exists());
}

/// `pendulum-fem run` of 5 steps without pictures or ParaView frames into `out`, with `sets`.
fn short_run(out: &std::path::Path, sets: &[&str]) -> Output {
    let mut cmd = common::bin();
    cmd.args(["run", "--quiet", "--out"])
        .arg(out)
        .args(common::NO_PICTURES)
        .args(["--set", "output.paraview=false", "--set", "time.end=0.05"]);
    for s in sets {
        cmd.args(["--set", s]);
    }
    let o = cmd.output().unwrap();
    assert!(o.status.success(), "{sets:?}: {}", stderr(&o));
    o
}

#[test]
fn a_torque_amplitude_without_a_profile_warns_naming_the_profile_key_and_changes_no_result() {
    let dir = common::scratch("ineffective-torque");
    let plain = short_run(&dir.join("plain"), &[]);
    let set = short_run(&dir.join("set"), &["torque.amplitude=2"]);
    let warning = "warning: torque.amplitude = 2 has no effect: no torque profile is set (set torque.profile to \
                   one of \"constant\", \"step\", \"ramp\", \"sine\" or \"table\")";
    assert!(stderr(&set).contains(warning), "{}", stderr(&set));
    assert!(!stderr(&plain).contains("warning:"), "{}", stderr(&plain));
    let results = |name: &str| std::fs::read(dir.join(name).join("results.csv")).unwrap();
    assert_eq!(
        results("plain"),
        results("set"),
        "the results are those of the defaults"
    );
    // the run keeps it with its warnings: in status.json, and in the summary it prints without
    // --quiet
    assert_eq!(status_of(&dir.join("set")).warnings, [warning]);
    let loud = common::bin()
        .args(["run", "--out"])
        .arg(dir.join("loud"))
        .args(common::NO_PICTURES)
        .args(["--set", "output.paraview=false", "--set", "time.end=0.05"])
        .args(["--set", "torque.amplitude=2"])
        .output()
        .unwrap();
    assert!(loud.status.success(), "{}", stderr(&loud));
    assert!(
        String::from_utf8_lossy(&loud.stdout).contains(warning),
        "{}",
        String::from_utf8_lossy(&loud.stdout)
    );
    assert!(status_of(&dir.join("plain")).warnings.is_empty());
}

#[test]
fn contact_keys_without_a_wall_and_modes_on_the_full_body_warn_naming_what_makes_them_act() {
    let dir = common::scratch("ineffective-wall");
    let o = short_run(&dir.join("out"), &["contact.stiffness=1e10", "model.modes=4"]);
    let msg = stderr(&o);
    for warning in [
        "warning: contact.stiffness = 1e10 has no effect: there is no wall (set wall.kind to \"rigid\" or \
         \"deformable\")",
        "warning: model.modes = 4 has no effect: the full body (model.kind = \"full\") has no modes (set \
         model.kind to \"reduced\")",
    ] {
        assert!(msg.contains(warning), "{warning:?} missing in:\n{msg}");
    }
    // where they act, nothing is said
    let o = short_run(&dir.join("wall"), &["contact.stiffness=1e10", "wall.kind=\"rigid\""]);
    assert!(!stderr(&o).contains("warning:"), "{}", stderr(&o));
}

#[test]
fn the_default_configuration_and_the_file_init_writes_warn_of_nothing() {
    let dir = common::scratch("no-warning");
    let file = dir.join("p.toml");
    assert!(common::bin().arg("init").arg(&file).output().unwrap().status.success());
    let o = short_run(&dir.join("default"), &[]);
    assert!(!stderr(&o).contains("warning:"), "{}", stderr(&o));
    let o = common::bin()
        .args(["run", "--quiet", "--config"])
        .arg(&file)
        .arg("--out")
        .arg(dir.join("init"))
        // every output on, as the file says: with them off, [output] keys would act on nothing
        .args(["--set", "time.end=0.05"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning:"), "{}", stderr(&o));
}

#[test]
fn out_of_range_values_name_the_key_and_the_allowed_range() {
    for (set, key) in [
        ("mesh.max_size=-0.1", "mesh.max_size"),
        ("material.poisson_ratio=0.6", "material.poisson_ratio"),
        ("time.dt=0", "time.dt"),
        ("geometry.hole_radius=0.07", "geometry.hole_radius"),
        ("mesh.order=3", "mesh.order"),
        ("solver.max_cutbacks=31", "solver.max_cutbacks"),
        ("solver.max_cutbacks=-1", "solver.max_cutbacks"),
        ("solver.max_cutbacks=often", "solver.max_cutbacks"),
    ] {
        let o = common::bin().args(["run", "--set", set]).output().unwrap();
        assert!(!o.status.success(), "{set} accepted");
        let msg = stderr(&o);
        assert!(msg.contains(key) && msg.contains("allowed"), "{set}: {msg}");
    }
}

#[test]
fn a_failing_step_names_step_time_and_residual_keeps_the_rows_and_writes_plots_and_status() {
    let dir = common::scratch("fail");
    let out = dir.join("out");
    // no cut-back: step 1 must fail
    let o = run_failing_every_step(&["solver.max_cutbacks=0"], &out);
    assert!(!o.status.success());
    let msg = stderr(&o);
    assert!(
        msg.contains("time step 1") && msg.contains("t = 0.000000 s") && msg.contains("residual"),
        "{msg}"
    );
    assert!(msg.contains("Try a smaller time.dt"), "a hint: {msg}");
    assert!(!msg.contains("caused by"), "the cause is already in the message: {msg}");
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 2, "header and the initial row: {csv}");
    assert!(lines[0].starts_with("time_s,theta_rad,omega_rad_s,alpha_rad_s2,kinetic_J,strain_J,gravity_J,total_J,hinge_fx_N,hinge_fy_N,von_mises_max_Pa,newton_iterations"));
    assert!(lines[1].starts_with("0,"));
    // the failed run still shows what it computed, and says how it ended
    for f in [
        "theta.png",
        "energy.png",
        "viewer.html",
        "pendulum.pvd",
        "frames/step_00000.vtu",
    ] {
        assert!(out.join(f).is_file(), "{f} missing after the failure");
    }
    let status = status_of(&out);
    assert_eq!(status.status, "failed");
    assert_eq!((status.step, status.time_s), (Some(0), Some(0.0)));
    assert!(
        status.error.as_deref().unwrap_or("").contains("time step 1"),
        "{status:?}"
    );
}

/// `pendulum-fem run` with `--set` of each of `extra`, on settings where every step fails: an
/// energy tolerance no update can reach and one Newton iteration, from an undeformed start (so
/// the initial equilibrium solve is not involved).
fn run_failing_every_step(extra: &[&str], out: &std::path::Path) -> Output {
    common::bin()
        .args(["run", "--quiet", "--set", "solver.max_iterations=1"])
        .args([
            "--set",
            "solver.tolerance=1e-300",
            "--set",
            "initial.elastic=undeformed",
        ])
        .args(extra.iter().flat_map(|s| ["--set", s]))
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

/// The smallest step length a failed run tried, from its error message.
fn smallest_dt_tried(msg: &str) -> f64 {
    let tail = msg
        .split("smallest dt tried ")
        .nth(1)
        .expect("the failure names its smallest step");
    tail.split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn a_failing_step_is_halved_down_to_the_meshs_wave_time_by_default_and_exactly_as_often_as_a_count_says() {
    let dir = common::scratch("cutbacks");
    // every step fails: the error names the shortest step tried
    let failing = |extra: &[&str], out: &str| {
        let o = run_failing_every_step(&[extra, &["time.dt=0.01"]].concat(), &dir.join(out));
        assert!(!o.status.success(), "{extra:?} ran");
        smallest_dt_tried(&stderr(&o))
    };
    let config = pendulum_fem::Config::default();
    let mesh = pendulum_fem::mesh::generate(&config).unwrap();
    let wave = pendulum_fem::Model::new(&config, mesh).unwrap().wave_time();
    // steel: a pressure wave of about 5 km/s crosses the tutorial mesh's thinnest element (at half
    // its altitude) in well under a microsecond
    assert!(wave > 1e-9 && wave < 1e-6, "wave time {wave:e} s");
    // "auto": halved until the step is no longer than the wave time, so the last one lies in
    // (wave/2, wave]: halving is exact in binary, the bound allows only the comparison's rounding
    let auto = failing(&[], "auto");
    assert!(
        auto <= wave * (1.0 + 1e-12) && auto > 0.5 * wave,
        "{auto:e} s against {wave:e} s"
    );
    // a count: exactly that many halvings, 0.01 / 2³
    let three = failing(&["solver.max_cutbacks=3"], "three");
    assert_eq!(three, 0.01 / 8.0);
}

#[test]
fn init_writes_a_commented_configuration_that_reads_back_as_the_defaults() {
    let dir = common::scratch("init");
    let file = dir.join("p.toml");
    let o = common::bin().arg("init").arg(&file).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("# m/s^2") || text.contains("m/s^2"));
    assert_eq!(
        pendulum_fem::Config::load(Some(&file), &[]).unwrap(),
        pendulum_fem::Config::default()
    );
    // a second init refuses to overwrite
    let o = common::bin().arg("init").arg(&file).output().unwrap();
    assert!(!o.status.success() && stderr(&o).contains("--force"));
}

#[test]
fn init_header_says_the_defaults_are_energy_momentum_from_a_rigid_start_and_how_to_get_the_tutorial() {
    let dir = common::scratch("init-header");
    let file = dir.join("p.toml");
    let o = common::bin().arg("init").arg(&file).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&file).unwrap();
    let header: String = text
        .lines()
        .take_while(|l| l.starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n");
    assert!(
        !header.contains("reproduce the NGSolve"),
        "the defaults do not reproduce it: {header}"
    );
    for words in [
        "energy-momentum",
        "rigid-body start",
        "time.scheme = \"trapezoidal\"",
        "initial.acceleration = \"zero\"",
    ] {
        assert!(header.contains(words), "the header should say {words:?}:\n{header}");
    }
    // and what it says is so: the defaults are that scheme and that start
    let defaults = pendulum_fem::Config::default();
    let as_toml = toml::to_string(&defaults).unwrap();
    assert!(
        as_toml.contains("scheme = \"energy-momentum\"") && as_toml.contains("acceleration = \"rigid\""),
        "{as_toml}"
    );
}

#[test]
fn help_lists_every_subcommand() {
    let o = common::bin().arg("--help").output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    for sub in ["run", "mesh", "modes", "init", "bench", "sweep"] {
        assert!(text.contains(sub), "--help lacks {sub}: {text}");
    }
}

#[test]
fn quiet_runs_print_nothing_on_success_and_only_the_error_on_failure() {
    let dir = common::scratch("quiet");
    let quiet = |out: &str, sets: &[&str]| {
        let mut c = common::bin();
        c.args([
            "run",
            "--quiet",
            "--set",
            "time.end=0.02",
            "--set",
            "output.paraview=false",
        ])
        .args(common::NO_PICTURES);
        for s in sets {
            c.args(["--set", s]);
        }
        c.arg("--out").arg(dir.join(out)).output().unwrap()
    };
    let ok = quiet("ok", &[]);
    assert!(ok.status.success(), "{}", stderr(&ok));
    assert_eq!(String::from_utf8_lossy(&ok.stdout), "", "stdout of a quiet run");
    assert_eq!(stderr(&ok), "", "stderr of a quiet run");
    assert!(dir.join("ok/results.csv").is_file(), "the run wrote its results");

    let short = common::bin()
        .args(["run", "-q", "--set", "time.end=0.02", "--set", "output.paraview=false"])
        .args(common::NO_PICTURES)
        .arg("--out")
        .arg(dir.join("short"))
        .output()
        .unwrap();
    assert!(
        short.status.success() && short.stdout.is_empty() && short.stderr.is_empty(),
        "-q: {short:?}"
    );

    let bad = quiet("bad", &["time.dt=0"]);
    assert!(!bad.status.success());
    assert_eq!(String::from_utf8_lossy(&bad.stdout), "", "stdout of a failed quiet run");
    assert!(
        stderr(&bad).starts_with("error: ") && stderr(&bad).contains("time.dt"),
        "{}",
        stderr(&bad)
    );
}

fn status_of(dir: &std::path::Path) -> pendulum_fem::run::status::RunStatus {
    pendulum_fem::run::status::RunStatus::read(&dir.join("status.json")).expect("status.json")
}

/// Every file below `dir`, relative, sorted.
fn files_below(dir: &std::path::Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p.strip_prefix(dir).unwrap().display().to_string());
            }
        }
    }
    out.sort();
    out
}

#[cfg(unix)]
#[test]
fn sigint_stops_at_a_step_boundary_with_consistent_outputs_and_exit_130() {
    let dir = common::scratch("sigint");
    let out = dir.join("out");
    // 500 steps take several seconds; the interrupt comes after about 20 frames, one per step
    let mut child = common::bin()
        .args([
            "run",
            "--quiet",
            "--set",
            "time.end=5",
            "--set",
            "output.every=1",
            "--out",
        ])
        .arg(&out)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let frames = out.join("frames");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    while std::fs::read_dir(&frames).map(|d| d.count()).unwrap_or(0) < 20 {
        assert!(std::time::Instant::now() < deadline, "no frames after 120 s");
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before the interrupt"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "stderr: {}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(stdout.lines().count(), 1, "a one-line summary: {stdout}");
    assert!(stdout.contains("interrupted at t = "), "{stdout}");

    let status = status_of(&out);
    assert_eq!(status.status, "interrupted");
    let (step, time) = (status.step.unwrap(), status.time_s.unwrap());
    assert!((19..500).contains(&step), "stopped at step {step}");
    assert!((time - step as f64 * 0.01).abs() < 1e-12, "time {time} of step {step}");
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let rows = csv.lines().count() - 1;
    let vtu = std::fs::read_dir(&frames).unwrap().count();
    assert_eq!(rows, step + 1, "CSV rows up to the last step");
    assert_eq!(vtu, rows, "one frame per CSV row");
    let pvd = std::fs::read_to_string(out.join("pendulum.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), vtu, "the .pvd lists every frame");
    assert!(pvd.trim_end().ends_with("</VTKFile>"));
    for f in [
        "theta.png",
        "energy.png",
        "displacement.gif",
        "von_mises.gif",
        "viewer.html",
    ] {
        assert!(out.join(f).is_file(), "{f} missing after the interrupt");
    }
    let partial: Vec<String> = files_below(&out)
        .into_iter()
        .filter(|f| f.ends_with(".partial"))
        .collect();
    assert!(partial.is_empty(), "{partial:?}");
}

#[test]
fn force_over_a_longer_earlier_run_leaves_no_file_of_it() {
    let dir = common::scratch("force");
    let out = dir.join("out");
    let run = |end: &str, force: bool| {
        let mut c = common::bin();
        c.args([
            "run",
            "--quiet",
            "--set",
            &format!("time.end={end}"),
            "--set",
            "output.every=1",
            "--out",
        ])
        .arg(&out);
        if force {
            c.arg("--force");
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
    };
    run("0.3", false);
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    assert_eq!(std::fs::read_dir(out.join("frames")).unwrap().count(), 31);
    let before: Vec<(String, std::time::SystemTime)> = files_below(&out)
        .into_iter()
        .map(|f| {
            let t = std::fs::metadata(out.join(&f)).unwrap().modified().unwrap();
            (f, t)
        })
        .collect();
    std::thread::sleep(std::time::Duration::from_millis(20));
    // a shorter run without pictures: nothing of the first run may survive
    let o = common::bin()
        .args([
            "run",
            "--quiet",
            "--force",
            "--set",
            "time.end=0.1",
            "--set",
            "output.plots=false",
            "--set",
            "output.every=1",
        ])
        .args(["--set", "output.animation=false", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let after = files_below(&out);
    let frames: Vec<&String> = after.iter().filter(|f| f.starts_with("frames")).collect();
    assert_eq!(frames.len(), 11, "steps 0..=10 only: {frames:?}");
    for name in ["theta.png", "energy.png", "displacement.gif", "von_mises.gif"] {
        assert!(!out.join(name).exists(), "stale {name} of the earlier run");
    }
    for (f, t) in before {
        if f == "notes.txt" {
            assert_eq!(
                std::fs::read_to_string(out.join(&f)).unwrap(),
                "mine",
                "other files are kept"
            );
            continue;
        }
        if let Ok(m) = std::fs::metadata(out.join(&f)) {
            assert!(m.modified().unwrap() > t, "{f} is a file of the earlier run");
        }
    }
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 12, "header and steps 0..=10");
    assert_eq!(status_of(&out).status, "ok");
}

#[cfg(unix)]
#[test]
fn bench_ngsolve_checks_its_inputs_before_timing_anything() {
    let dir = common::scratch("bench-inputs");
    let missing = dir.join("no_such_script.py");
    let o = common::bin()
        .args(["bench", "run", "--repeats", "1", "--ngsolve", "python3", "--anchor"])
        .arg(&missing)
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("no_such_script.py") && stderr(&o).contains("--anchor"),
        "{}",
        stderr(&o)
    );
    assert!(
        o.stdout.is_empty(),
        "nothing was timed: {}",
        String::from_utf8_lossy(&o.stdout)
    );
    // a Python without NGSolve is refused by name, also before any timing
    let script = dir.join("script.py");
    std::fs::write(&script, "print('never run')\n").unwrap();
    let o = common::bin()
        .args(["bench", "run", "--repeats", "1", "--ngsolve", "/bin/false", "--anchor"])
        .arg(&script)
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("--ngsolve /bin/false") && stderr(&o).contains("ngsolve"),
        "{}",
        stderr(&o)
    );
    assert!(o.stdout.is_empty());
}

/// θ of the NGSolve reference `tests/data/NAME` (see `tests/data/README.md`) as `(t, θ)`.
fn ngsolve_theta(name: &str) -> Vec<(f64, f64)> {
    let path = common::root().join("tests/data").join(name);
    let (names, rows) = pendulum_fem::store::Table::read(&path)
        .map(|t| (t.names, t.rows))
        .unwrap();
    assert_eq!(names[..2], ["t_s", "theta_rad"]);
    rows.into_iter().map(|r| (r[0], r[1])).collect()
}

#[test]
fn the_tutorials_exact_reproduction_runs_through_the_cli_with_the_watchdog_on_and_matches_ngsolve() {
    // The book's way to reproduce the tutorial (docs/src/basics.md): its Newmark rule and its zero initial
    // acceleration, every other setting the default (the energy watchdog at 0.01 included). The
    // zero start loses 1.2e-4 J in its first step by construction; judged against the energy the
    // swing has available (3.75 J) that is 3.3e-5, not a divergence.
    let dir = common::scratch("tutorial");
    let out = common::bin()
        .args(["run", "--quiet", "--out"])
        .arg(&dir)
        .args([
            "--force",
            "--set",
            "time.scheme=\"trapezoidal\"",
            "--set",
            "initial.acceleration=\"zero\"",
        ])
        .args([
            "--set",
            "output.paraview=false",
            "--set",
            "output.animation=false",
            "--set",
            "output.viewer=false",
        ])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let (names, rows) = pendulum_fem::store::Table::read(&dir.join("results.csv"))
        .map(|t| (t.names, t.rows))
        .unwrap();
    let (t, theta) = (
        names.iter().position(|c| c == "time_s").unwrap(),
        names.iter().position(|c| c == "theta_rad").unwrap(),
    );
    let reference = ngsolve_theta("tutorial_theta_a0_zero.csv");
    assert_eq!(rows.len(), reference.len(), "one row per reference step");
    for (row, (t_ref, _)) in rows.iter().zip(&reference) {
        assert!((row[t] - t_ref).abs() < 1e-9, "time {} vs {t_ref}", row[t]);
    }
    let worst = rows
        .iter()
        .zip(&reference)
        .map(|(row, (_, theta_ref))| (row[theta] - theta_ref).abs().to_degrees())
        .max_of();
    // the bar: 0.01° at every step
    assert!(worst < 0.01, "largest |θ − θ_NGSolve| = {worst} deg");
}
