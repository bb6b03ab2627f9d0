//! `run --checkpoint-every N` and `run --restart DIR`: a run killed at any moment and restarted
//! from its last checkpoint, or a finished run continued to a later `time.end`, writes exactly the
//! results of an uninterrupted run.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// With [`common::NO_PICTURES`], few outputs: results.csv and every 50th ParaView frame.
const EVERY_50TH_FRAME: [&str; 2] = ["--set", "output.paraview_every=50"];

fn run(args: &[&str], out: &Path) -> Output {
    let o = common::bin()
        .arg("run")
        .arg("--quiet")
        .args(common::NO_PICTURES)
        .args(EVERY_50TH_FRAME)
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "run {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

fn restart(args: &[&str], dir: &Path) -> Output {
    common::bin()
        .args(["run", "--quiet"])
        .args(args)
        .arg("--restart")
        .arg(dir)
        .output()
        .unwrap()
}

fn read(path: PathBuf) -> Vec<u8> {
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn rows(dir: &Path) -> usize {
    std::fs::read_to_string(dir.join("results.csv"))
        .map(|t| t.lines().count().saturating_sub(1))
        .unwrap_or(0)
}

#[test]
fn a_run_killed_with_sigkill_and_restarted_writes_the_uninterrupted_results_byte_for_byte() {
    let dir = common::scratch("kill");
    let (whole, killed) = (dir.join("whole"), dir.join("killed"));
    run(&["--set", "time.end=6"], &whole);
    let mut child = common::bin()
        .args(["run", "--quiet", "--checkpoint-every", "10", "--set", "time.end=6"])
        .args(common::NO_PICTURES)
        .args(EVERY_50TH_FRAME)
        .arg("--out")
        .arg(&killed)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(300);
    while rows(&killed) < 300 {
        assert!(std::time::Instant::now() < deadline, "fewer than 300 rows after 300 s");
        assert!(child.try_wait().unwrap().is_none(), "the run ended before the kill");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let kill = Command::new("kill")
        .args(["-KILL", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    child.wait().unwrap();
    let at_kill = rows(&killed);
    eprintln!("killed with {at_kill} rows in results.csv");
    assert!((300..601).contains(&at_kill), "killed with {at_kill} of 601 rows");
    let status = std::fs::read_to_string(killed.join("status.json")).unwrap();
    assert!(status.contains("\"running\""), "a killed run says running: {status}");
    let o = restart(&[], &killed);
    assert!(o.status.success(), "restart: {}", String::from_utf8_lossy(&o.stderr));
    assert!(
        read(killed.join("results.csv")) == read(whole.join("results.csv")),
        "results.csv differs"
    );
    assert!(
        read(killed.join("pendulum.pvd")) == read(whole.join("pendulum.pvd")),
        "pendulum.pvd differs"
    );
    assert!(read(killed.join("frames/step_00600.vtu")) == read(whole.join("frames/step_00600.vtu")));
    let status = std::fs::read_to_string(killed.join("status.json")).unwrap();
    assert!(
        status.contains("\"ok\"") && status.contains("\"step\": 600"),
        "{status}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn restarting_a_finished_run_with_a_larger_end_continues_it() {
    let dir = common::scratch("continue");
    let (whole, short) = (dir.join("whole"), dir.join("short"));
    run(&["--set", "time.end=1"], &whole);
    run(&["--checkpoint-every", "30", "--set", "time.end=0.5"], &short);
    assert_eq!(rows(&short), 51);
    let o = restart(&["--set", "time.end=1"], &short);
    assert!(o.status.success(), "restart: {}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(rows(&short), 101);
    assert!(
        read(short.join("results.csv")) == read(whole.join("results.csv")),
        "results.csv differs"
    );
    assert!(
        read(short.join("pendulum.pvd")) == read(whole.join("pendulum.pvd")),
        "pendulum.pvd differs"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_restart_without_a_checkpoint_or_with_another_model_is_a_clear_error() {
    let dir = common::scratch("errors");
    let (plain, with) = (dir.join("plain"), dir.join("with"));
    run(&["--set", "time.end=0.05"], &plain);
    let o = restart(&[], &plain);
    let msg = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && msg.contains("checkpoint.toml") && msg.contains("--checkpoint-every"),
        "{msg}"
    );
    run(&["--checkpoint-every", "2", "--set", "time.end=0.05"], &with);
    let csv = read(with.join("results.csv"));
    let o = restart(&["--set", "material.density=7000"], &with);
    let msg = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && msg.contains("another model"), "{msg}");
    assert!(
        read(with.join("results.csv")) == csv,
        "a refused restart leaves results.csv alone"
    );
    let o = common::bin()
        .args(["run", "--checkpoint-every", "0", "--out"])
        .arg(dir.join("zero"))
        .output()
        .unwrap();
    let msg = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && msg.contains("--checkpoint-every 0") && msg.contains(">= 1"),
        "{msg}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_restart_finds_the_same_model_through_a_relative_torque_table_and_the_deformable_wall_but_not_an_edited_table() {
    // checkpoint.toml names the table by its absolute path; the fingerprint covers the table's
    // values, not the path, and the deformable wall's block like the run itself
    let dir = common::scratch("files");
    let table = "time_s,torque_Nm\n0,0\n0.02,0.5\n1,0\n";
    std::fs::write(dir.join("t.csv"), table).unwrap();
    let sets = [
        "--set",
        "torque.profile=\"table\"",
        "--set",
        "torque.file=\"t.csv\"",
        "--set",
        "wall.kind=\"deformable\"",
    ];
    let in_dir = |args: &[&str], out: &str| {
        let o = common::bin()
            .args(["run", "--quiet"])
            .args(common::NO_PICTURES)
            .args(EVERY_50TH_FRAME)
            .args(sets)
            .args(args)
            .args(["--out", out])
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "run {args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    };
    in_dir(&["--set", "time.end=0.05"], "whole");
    in_dir(&["--checkpoint-every", "2", "--set", "time.end=0.03"], "short");
    // from another folder
    let o = restart(&["--set", "time.end=0.05"], &dir.join("short"));
    assert!(o.status.success(), "restart: {}", String::from_utf8_lossy(&o.stderr));
    assert!(
        read(dir.join("short/results.csv")) == read(dir.join("whole/results.csv")),
        "results.csv differs"
    );
    std::fs::write(dir.join("t.csv"), table.replace("0.5", "0.51")).unwrap();
    let o = restart(&["--set", "time.end=0.07"], &dir.join("short"));
    let msg = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success()
            && msg.contains("another model")
            && msg.contains("the torque table")
            && msg.contains("t.csv"),
        "{msg}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_wall_run_restarted_from_an_earlier_checkpoint_cuts_and_appends_its_files_to_the_uninterrupted_ones() {
    let dir = common::scratch("wall");
    let (whole, early) = (dir.join("whole"), dir.join("early"));
    let wall = |end: &'static str| ["--set", "wall.kind=\"rigid\"", "--checkpoint-every", "10", "--set", end];
    run(&wall("time.end=1"), &whole);
    run(&wall("time.end=0.5"), &early);
    let names = ["results.csv", "events.csv", "impacts.csv"];
    let uninterrupted = names.map(|name| read(whole.join(name)));
    // the files of the whole run reach past the checkpoint of the early one, as those of a run
    // killed after its checkpoint at 0.5 s do: the second impact's events (about 0.72 s) among them
    let events = String::from_utf8(uninterrupted[1].clone()).unwrap();
    let after: Vec<&str> = events
        .lines()
        .skip(1)
        .filter(|l| l.split(',').next().unwrap().parse::<f64>().unwrap() > 0.5)
        .collect();
    assert!(!after.is_empty(), "no event after 0.5 s:\n{events}");
    std::fs::copy(early.join("checkpoint.snap"), whole.join("checkpoint.snap")).unwrap();
    for folder in [&whole, &early] {
        let o = restart(&["--set", "time.end=1"], folder);
        assert!(o.status.success(), "restart: {}", String::from_utf8_lossy(&o.stderr));
        for (name, bytes) in names.iter().zip(&uninterrupted) {
            assert!(
                read(folder.join(name)) == *bytes,
                "{}: {name} differs from the uninterrupted run's",
                folder.display()
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
