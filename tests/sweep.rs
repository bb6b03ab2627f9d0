//! `pendulum-fem sweep`: a grid of cases gives one folder and one summary row per case, equal to
//! separate runs; job-array tasks plus `--gather` give the local sweep's summary; a failed case is
//! a failed row and never stops the others; an interrupted sweep resumed gives the summary of an
//! uninterrupted one. The cases are short (`time.end = 0.1` to `0.5`) default runs.

use crate::common;
use common::Extremes;

use std::path::Path;
use std::process::{Command, Output};

use pendulum_fem::commands::run::EnergyAudit;
use pendulum_fem::commands::sweep::case::split_csv_line;
use pendulum_fem::post::PeriodEstimator;
use pendulum_fem::simulation::{Model, StepRecord};
use pendulum_fem::{mesh, Config};

/// The binary, without the job-array variables of the environment the tests may run in.
fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// `(header, rows)` of a summary, cells as text.
fn table(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines().map(|l| split_csv_line(l).unwrap());
    let header = lines.next().expect("a header");
    (header, lines.collect())
}

/// The table without the wall-time column (the one value that differs from one run to the next).
fn without_wall_time(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let (header, rows) = table(path);
    let c = header
        .iter()
        .position(|h| h == "wall_time_s")
        .expect("a wall_time_s column");
    let drop = |mut v: Vec<String>| {
        v.remove(c);
        v
    };
    (drop(header), rows.into_iter().map(drop).collect())
}

fn cell<'a>(header: &[String], row: &'a [String], name: &str) -> &'a str {
    let c = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    &row[c]
}

fn number(header: &[String], row: &[String], name: &str) -> f64 {
    let text = cell(header, row, name);
    text.parse()
        .unwrap_or_else(|_| panic!("{name} = `{text}` is not a number"))
}

/// Metrics recomputed from a run's `results.csv` and its configuration by their definitions:
/// `(final time, steps, Newton iterations, θ min °, θ max °, period, von Mises max, energy error)`.
fn metrics_from_csv(run: &Path, cfg: &Config) -> [Option<f64>; 8] {
    let (names, rows) = pendulum_fem::store::Table::read(&run.join("results.csv"))
        .map(|t| (t.names, t.rows))
        .unwrap();
    let col = |n: &str| names.iter().position(|c| c == n).unwrap();
    let model = Model::new(cfg, mesh::generate(cfg).unwrap()).unwrap();
    let mut audit = EnergyAudit::of(&model);
    let mut period = PeriodEstimator::default();
    let (mut lo, mut hi, mut vm, mut its) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64, 0.0);
    for (step, r) in rows.iter().enumerate() {
        let record = StepRecord {
            step,
            time: r[col("time_s")],
            theta: r[col("theta_rad")],
            kinetic: r[col("kinetic_J")],
            strain: r[col("strain_J")],
            gravity: r[col("gravity_J")],
            total: r[col("total_J")],
            torque_work: r[col("torque_work_J")],
            ..Default::default()
        };
        audit.push(&record).unwrap_or_else(|e| panic!("{}: {e}", run.display()));
        period.push(record.time, record.theta);
        lo = [lo, record.theta].into_iter().min_of();
        hi = [hi, record.theta].into_iter().max_of();
        vm = [vm, r[col("von_mises_max_Pa")]].into_iter().max_of();
        its += r[col("newton_iterations")];
    }
    let last = rows.last().unwrap();
    [
        Some(last[col("time_s")]),
        Some((rows.len() - 1) as f64),
        Some(its),
        Some(lo.to_degrees()),
        Some(hi.to_degrees()),
        period.period(),
        Some(vm),
        Some(audit.error()),
    ]
}

const SHORT: [&str; 2] = ["--set", "time.end=0.1"];

#[test]
fn a_three_by_two_grid_gives_six_case_folders_whose_rows_equal_six_separate_runs() {
    let dir = common::scratch("grid");
    let out = dir.join("sweep");
    let o = common::bin()
        .args(["sweep", "--quiet", "--jobs", "2"])
        .args([
            "--vary",
            "material.youngs_modulus=1e8,1e9,2.1e11",
            "--vary",
            "initial.angle_deg=10:30:2",
        ])
        .args(SHORT)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("6 cases"), "{}", stdout(&o));
    let (header, rows) = table(&out.join("summary.csv"));
    assert_eq!(
        header,
        [
            "material.youngs_modulus",
            "initial.angle_deg",
            "final_time_s",
            "steps",
            "newton_iterations",
            "wall_time_s",
            "theta_min_deg",
            "theta_max_deg",
            "period_s",
            "von_mises_max_Pa",
            "energy_error",
            "status",
            "message"
        ]
    );
    assert_eq!(rows.len(), 6);
    let expected = [
        ("1e8", "10"),
        ("1e8", "30"),
        ("1e9", "10"),
        ("1e9", "30"),
        ("2.1e11", "10"),
        ("2.1e11", "30"),
    ];
    let names = [
        "final_time_s",
        "steps",
        "newton_iterations",
        "theta_min_deg",
        "theta_max_deg",
        "period_s",
        "von_mises_max_Pa",
        "energy_error",
    ];
    for (k, ((e, angle), row)) in expected.iter().zip(&rows).enumerate() {
        assert_eq!(
            (row[0].as_str(), row[1].as_str()),
            (*e, *angle),
            "case {k}: the grid order"
        );
        assert_eq!(cell(&header, row, "status"), "ok", "case {k}: {row:?}");
        let case = out.join(format!("case-{k:04}"));
        for f in ["config.toml", "results.csv", "status.json", "summary.csv"] {
            assert!(case.join(f).is_file(), "case {k}: {f} missing");
        }
        assert!(!case.join("theta.png").exists(), "a case writes no plots by default");
        // the same case as a separate run, from the command line
        let run = dir.join(format!("run-{k}"));
        let r = common::bin()
            .args(["run", "--quiet"])
            .args(SHORT)
            .args(["--set", &format!("material.youngs_modulus={e}")])
            .args(["--set", &format!("initial.angle_deg={angle}")])
            .arg("--out")
            .arg(&run)
            .output()
            .unwrap();
        assert!(r.status.success(), "{}", stderr(&r));
        let a = std::fs::read(case.join("results.csv")).unwrap();
        let b = std::fs::read(run.join("results.csv")).unwrap();
        assert!(a == b, "case {k}: results.csv differs from the separate run's");
        let cfg = Config::load(Some(&case.join("config.toml")), &[]).unwrap();
        assert_eq!(cfg.material.youngs_modulus, e.parse::<f64>().unwrap());
        let from_run = metrics_from_csv(&run, &cfg);
        for (name, want) in names.iter().zip(from_run) {
            let got = cell(&header, row, name);
            match want {
                Some(w) => assert_eq!(
                    got.parse::<f64>().map(f64::to_bits),
                    Ok(w.to_bits()),
                    "case {k}: {name} = {got}, the separate run gives {w}"
                ),
                None => assert_eq!(got, "", "case {k}: {name}"),
            }
        }
    }
    for key in ["material_youngs_modulus", "initial_angle_deg"] {
        let png = out.join(format!("summary_{key}.png"));
        assert!(
            std::fs::metadata(&png).map(|m| m.len() > 10_000).unwrap_or(false),
            "{} missing",
            png.display()
        );
    }
}

/// The arguments of the study of the job-array and resume tests.
fn study(end: &str) -> Vec<String> {
    [
        "--vary",
        "material.youngs_modulus=1e8..2.1e11:3",
        "--vary",
        "initial.angle_deg=10,20",
        "--set",
        end,
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

#[test]
fn case_index_for_every_case_then_gather_gives_the_local_summary() {
    let dir = common::scratch("array");
    let (local, array) = (dir.join("local"), dir.join("array"));
    let args = study("time.end=0.1");
    let o = common::bin()
        .args(["sweep", "--quiet"])
        .args(&args)
        .arg("--out")
        .arg(&local)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let o = common::bin().args(["sweep", "--list"]).args(&args).output().unwrap();
    assert_eq!(stdout(&o).trim(), "6", "--list prints the number of cases");
    for k in 0..6 {
        let mut task = common::bin();
        task.args(["sweep", "--quiet"]).args(&args).arg("--out").arg(&array);
        // the scheduler's variable or the option
        match k % 2 {
            0 => task.env("SLURM_ARRAY_TASK_ID", k.to_string()),
            _ => task.args(["--case-index", &k.to_string()]),
        };
        let o = task.output().unwrap();
        assert!(o.status.success(), "case {k}: {}", stderr(&o));
        assert!(!array.join("summary.csv").exists(), "a task writes no summary");
    }
    let o = common::bin().args(["sweep", "--gather"]).arg(&array).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    // equal apart from the wall times: every other cell as text, so numbers bit for bit
    assert_eq!(
        without_wall_time(&array.join("summary.csv")),
        without_wall_time(&local.join("summary.csv"))
    );
    for k in 0..6 {
        let case = format!("case-{k:04}/results.csv");
        assert!(
            std::fs::read(array.join(&case)).unwrap() == std::fs::read(local.join(&case)).unwrap(),
            "{case}"
        );
    }
    for index in [vec!["--case-index", "6"], vec!["--case-index", "99"]] {
        let o = common::bin()
            .args(["sweep"])
            .args(&args)
            .args(&index)
            .arg("--out")
            .arg(&array)
            .output()
            .unwrap();
        assert!(!o.status.success());
        let msg = stderr(&o);
        assert!(
            msg.contains("out of range") && msg.contains("6 cases") && msg.contains("0 to 5"),
            "{msg}"
        );
    }
    // a missing case is listed and makes the gather fail
    std::fs::remove_file(array.join("case-0003/summary.csv")).unwrap();
    let o = common::bin()
        .args(["sweep", "--gather"])
        .arg(&array)
        .arg("--no-plots")
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("1 of 6 cases have no result (cases 3)"),
        "{}",
        stderr(&o)
    );
    let (header, rows) = table(&array.join("summary.csv"));
    assert_eq!(cell(&header, &rows[3], "status"), "pending");
}

#[test]
fn a_failing_case_is_marked_failed_with_its_message_and_the_others_complete() {
    let dir = common::scratch("failing");
    let file = dir.join("study.toml");
    std::fs::write(
        &file,
        r#"set = ["time.end = 0.1"]

[[case]]
initial.angle_deg = 10

[[case]]   # a configuration error
material.youngs_modulus = -1

[[case]]   # a solver failure: a tolerance no update reaches, one iteration, no cut-back
solver.tolerance = 1e-300
solver.max_iterations = 1
solver.max_cutbacks = 0
initial.elastic = "undeformed"

[[case]]
initial.angle_deg = 30
"#,
    )
    .unwrap();
    let out = dir.join("sweep");
    let o = common::bin()
        .args(["sweep", "--quiet", "--file"])
        .arg(&file)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("2 of 4 cases failed (cases 1, 2"), "{}", stderr(&o));
    let (header, rows) = table(&out.join("summary.csv"));
    assert_eq!(
        &header[..6],
        [
            "initial.angle_deg",
            "material.youngs_modulus",
            "solver.tolerance",
            "solver.max_iterations",
            "solver.max_cutbacks",
            "initial.elastic"
        ]
    );
    let status: Vec<&str> = rows.iter().map(|r| cell(&header, r, "status")).collect();
    assert_eq!(status, ["ok", "failed", "failed", "ok"]);
    let config_error = cell(&header, &rows[1], "message");
    assert!(
        config_error.contains("material.youngs_modulus") && config_error.contains("allowed"),
        "{config_error}"
    );
    let solver = cell(&header, &rows[2], "message");
    assert!(solver.contains("time step 1") && solver.contains("Newton"), "{solver}");
    // the failed run reached step 0 at t = 0; its other metrics are empty
    assert_eq!(
        (
            cell(&header, &rows[2], "final_time_s"),
            cell(&header, &rows[2], "steps")
        ),
        ("0", "0")
    );
    assert_eq!(cell(&header, &rows[2], "von_mises_max_Pa"), "");
    assert_eq!(
        cell(&header, &rows[2], "initial.elastic"),
        "undeformed",
        "strings without quotes"
    );
    assert_eq!(
        cell(&header, &rows[0], "material.youngs_modulus"),
        "",
        "a key the case leaves alone"
    );
    for k in [0, 3] {
        assert_eq!(number(&header, &rows[k], "final_time_s"), 0.1);
    }
    assert!(
        !out.join("case-0001/config.toml").exists(),
        "no resolved configuration for an invalid one"
    );
}

#[cfg(unix)]
#[test]
fn an_interrupted_sweep_resumed_gives_the_summary_of_an_uninterrupted_one() {
    let dir = common::scratch("resume");
    let (whole, parts) = (dir.join("whole"), dir.join("parts"));
    // ten cases of 50 steps
    let args = ["--vary", "initial.angle_deg=5:50:10", "--set", "time.end=0.5"];
    let o = common::bin()
        .args(["sweep", "--quiet", "--no-plots", "--jobs", "2"])
        .args(args)
        .arg("--out")
        .arg(&whole)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let mut child = common::bin()
        .args(["sweep", "--quiet", "--no-plots", "--jobs", "1"])
        .args(args)
        .arg("--out")
        .arg(&parts)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    while !parts.join("case-0001/summary.csv").exists() {
        assert!(std::time::Instant::now() < deadline, "no finished case after 120 s");
        assert!(
            child.try_wait().unwrap().is_none(),
            "the sweep ended before the interrupt"
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(stderr(&o).contains("--resume"), "{}", stderr(&o));
    let (header, rows) = table(&parts.join("summary.csv"));
    let status: Vec<&str> = rows.iter().map(|r| cell(&header, r, "status")).collect();
    let done = status.iter().filter(|s| **s == "ok").count();
    assert!((2..10).contains(&done), "finished before the interrupt: {status:?}");
    assert!(
        status[..done].iter().all(|s| *s == "ok") && status[done..].iter().all(|s| *s == "pending"),
        "{status:?}"
    );
    // the case that was running was stopped at a step boundary and left without a row
    assert!(!parts.join(format!("case-{done:04}/summary.csv")).exists());
    let finished_at: Vec<_> = (0..done)
        .map(|k| {
            std::fs::metadata(parts.join(format!("case-{k:04}/results.csv")))
                .unwrap()
                .modified()
                .unwrap()
        })
        .collect();
    // without --resume the folder is refused, untouched
    let o = common::bin()
        .args(["sweep", "--quiet"])
        .args(args)
        .arg("--out")
        .arg(&parts)
        .output()
        .unwrap();
    assert!(!o.status.success() && stderr(&o).contains("--resume"), "{}", stderr(&o));
    let o = common::bin()
        .args(["sweep", "--no-plots", "--resume"])
        .args(args)
        .arg("--out")
        .arg(&parts)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains(&format!("{done} finished before")),
        "{}",
        stdout(&o)
    );
    for (k, t) in finished_at.iter().enumerate() {
        let now = std::fs::metadata(parts.join(format!("case-{k:04}/results.csv")))
            .unwrap()
            .modified()
            .unwrap();
        assert_eq!(now, *t, "case {k} ran again");
    }
    assert_eq!(
        without_wall_time(&parts.join("summary.csv")),
        without_wall_time(&whole.join("summary.csv"))
    );
}

#[test]
fn resume_keeps_cases_whose_outputs_changed_and_refuses_cases_run_with_another_configuration() {
    let dir = common::scratch("stale");
    let out = dir.join("sweep");
    let args = [
        "--quiet",
        "--no-plots",
        "--vary",
        "initial.angle_deg=10,20",
        "--set",
        "time.end=0.05",
    ];
    let o = common::bin()
        .arg("sweep")
        .args(args)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let o = common::bin()
        .arg("sweep")
        .args(args)
        .args(["--resume", "--all-outputs"])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "other outputs are no other cases: {}", stderr(&o));
    let o = common::bin()
        .arg("sweep")
        .args(args)
        .args(["--resume", "--set", "time.dt=0.005"])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("case-0000 was run with another configuration"),
        "{}",
        stderr(&o)
    );
    let o = common::bin()
        .args(["sweep", "--quiet", "--vary", "initial.angle_deg=10,30"])
        .arg("--out")
        .arg(&out)
        .arg("--resume")
        .output()
        .unwrap();
    assert!(
        !o.status.success() && stderr(&o).contains("another sweep"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn bad_vary_arguments_name_the_argument_and_the_allowed_forms() {
    for bad in [
        "material.youngs_modulus",
        "material.youngs_modulus=1:2",
        "initial.angle_deg=0..10:3",
        "E=1,2",
    ] {
        let o = common::bin().args(["sweep", "--list", "--vary", bad]).output().unwrap();
        assert!(!o.status.success(), "{bad} accepted");
        let msg = stderr(&o);
        assert!(
            msg.contains(&format!("--vary {bad}")) && msg.contains("linear range") && msg.contains("log range"),
            "{bad}: {msg}"
        );
    }
    let o = common::bin()
        .args(["sweep", "--list", "--vary", "material.youngs_modulu=1,2"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("material.youngs_modulu is not a configuration key"),
        "{}",
        stderr(&o)
    );
    let o = common::bin()
        .args([
            "sweep",
            "--list",
            "--zip",
            "--vary",
            "initial.angle_deg=1,2",
            "--vary",
            "gravity.g=1,2,3",
        ])
        .output()
        .unwrap();
    assert!(!o.status.success() && stderr(&o).contains("--zip"), "{}", stderr(&o));
    let o = common::bin()
        .args([
            "sweep",
            "--list",
            "--zip",
            "--vary",
            "initial.angle_deg=1,2",
            "--vary",
            "gravity.g=1:3:2",
        ])
        .output()
        .unwrap();
    assert_eq!(stdout(&o).trim(), "2", "zipped: {}", stderr(&o));
}
