//! Generated meshes are kept on disk (`mesh::cache`) and read back exactly: a run whose mesh was
//! read writes the same results, byte for byte, as one that meshed. A binary of its own, so that
//! no other test's meshes fill the process's last-mesh store between the steps of the first test.

use crate::common;

use std::path::Path;
use std::process::Stdio;

use pendulum_fem::mesh::{self, cache};
use pendulum_fem::reduced::cache::with_folder;
use pendulum_fem::Config;

#[test]
fn a_generated_mesh_is_kept_on_disk_read_back_exactly_and_a_damaged_file_or_a_refused_configuration_is_not_served() {
    let dir = common::scratch("library");
    let cfg = Config::default();
    let made = mesh::generate_with_stats(&cfg).expect("mesh").0;
    let path = cache::file(&dir, cache::key(&cfg));
    with_folder(Some(dir.clone()), || {
        mesh::forget_last();
        assert_eq!(mesh::generate(&cfg).expect("mesh"), made, "meshed");
        let kept = std::fs::read(&path).expect("the mesh's file is written");
        assert_eq!(kept, cache::to_bytes(&made, cache::key(&cfg)));
        mesh::forget_last();
        assert_eq!(mesh::generate(&cfg).expect("mesh"), made, "read back");
        std::fs::write(&path, &kept[..kept.len() / 2]).expect("truncate");
        mesh::forget_last();
        assert_eq!(mesh::generate(&cfg).expect("mesh"), made, "meshed anew");
        assert_eq!(std::fs::read(&path).expect("file"), kept, "and the file replaced");
        // a configuration the mesher refuses gets its error with a mesh on disk, also one whose
        // sections JSON would write as the default's (an infinite size is `null` there, as an
        // absent one)
        let mut refused = cfg.clone();
        refused.mesh.hinge_edge_size = Some(f64::INFINITY);
        match mesh::generate(&refused) {
            Err(pendulum_fem::Error::Geometry(m)) => assert!(m.contains("mesh.hinge_edge_size"), "{m}"),
            other => panic!(
                "expected the geometry error, got {:?}",
                other.map(|m| m.triangles.len())
            ),
        }
    });
    // with the disk off nothing is written
    let off = common::scratch("off");
    with_folder(None, || {
        mesh::forget_last();
        assert_eq!(mesh::generate(&cfg).expect("mesh"), made);
    });
    assert_eq!(std::fs::read_dir(&off).expect("folder").count(), 0);
}

/// `pendulum-fem run` with the cache in `cache` (`off`: none) into `out`; its results.csv.
fn run(cache: &str, out: &Path) -> Vec<u8> {
    let status = common::bin()
        .args(["run", "-q", "--force", "--out"])
        .arg(out)
        .args([
            "--set",
            "time.end=0.2",
            "--set",
            "wall.kind=\"rigid\"",
            "--set",
            "initial.angle_deg=60",
        ])
        .args(["--set", "output.plots=false", "--set", "output.animation=false"])
        .args(["--set", "output.paraview=false", "--set", "output.viewer=false"])
        .env("PENDULUM_FEM_CACHE", cache)
        .stdout(Stdio::null())
        .status()
        .expect("pendulum-fem runs");
    assert!(status.success(), "run with the cache {cache}");
    std::fs::read(out.join("results.csv")).expect("results.csv")
}

#[test]
fn a_run_whose_mesh_was_read_writes_the_results_of_one_that_meshed() {
    let (dir, out) = (common::scratch("cli"), common::scratch("cli-out"));
    let folder = dir.to_str().expect("a UTF-8 path");
    let meshed = run(folder, &out.join("first"));
    let files: Vec<String> = std::fs::read_dir(&dir)
        .expect("cache folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        files.iter().any(|f| f.starts_with("mesh-")),
        "the first run keeps its mesh: {files:?}"
    );
    let read = run(folder, &out.join("second"));
    let without = run("off", &out.join("off"));
    assert_eq!(read, meshed, "the run that read its mesh");
    assert_eq!(without, meshed, "the run without a cache");
}
