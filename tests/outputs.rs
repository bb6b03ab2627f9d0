//! The frame writers: plots, animations, ParaView files, output folders and flags.

use crate::common;
use common::{plate, tools};

use std::collections::HashSet;
use std::path::Path;
use std::time::Instant;

use pendulum_fem::config::Output;
use pendulum_fem::render::FrameWriters;
use pendulum_fem::run::prepare_output_dir;
use plate::*;

/// Frame count and distinct palette indices of a GIF.
fn decode_gif(path: &Path) -> (usize, usize, (u16, u16)) {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::Indexed);
    let mut dec = opts.read_info(std::fs::File::open(path).unwrap()).unwrap();
    let size = (dec.width(), dec.height());
    let (mut frames, mut colours) = (0, HashSet::new());
    while let Some(f) = dec.read_next_frame().unwrap() {
        frames += 1;
        colours.extend(f.buffer.iter().copied());
    }
    (frames, colours.len(), size)
}

/// Size and distinct colours of an RGB(A) PNG.
fn decode_png(path: &Path) -> (u32, u32, usize) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let colours: HashSet<&[u8]> = buf[..info.buffer_size()].chunks(channels).map(|p| &p[..3]).collect();
    (info.width, info.height, colours.len())
}

#[test]
fn gifs_have_one_frame_per_written_step_and_show_many_colours() {
    let dir = common::scratch("gifs");
    let mesh = plate_mesh(2, 12);
    let output = Output {
        every: 2,
        plots: false,
        paraview: false,
        viewer: false,
        ..all_outputs()
    };
    let paths = run(&dir, &mesh, &output, 40, 0.01);
    for name in ["displacement.gif", "von_mises.gif"] {
        let path = dir.join(name);
        assert!(paths.contains(&path), "{name} not reported as written");
        let (frames, colours, size) = decode_gif(&path);
        assert_eq!(frames, 21, "{name}: steps 0, 2, …, 40");
        assert!(colours > 40, "{name}: only {colours} distinct colours");
        assert_eq!(size, (640, 600));
    }
}

#[test]
fn animation_frames_are_bounded_by_max_frames_and_end_on_the_last_step() {
    let dir = common::scratch("bounded");
    let mesh = plate_mesh(1, 4);
    let output = Output {
        max_frames: 16,
        plots: false,
        paraview: false,
        viewer: false,
        ..all_outputs()
    };
    run(&dir, &mesh, &output, 300, 0.002);
    let (frames, _, _) = decode_gif(&dir.join("von_mises.gif"));
    assert!((8..=16).contains(&frames), "{frames} frames for max_frames = 16");
}

#[test]
fn plots_are_pngs_with_axes_curves_and_text() {
    let dir = common::scratch("plots");
    let mesh = plate_mesh(1, 4);
    let output = Output {
        animation: false,
        paraview: false,
        viewer: false,
        ..all_outputs()
    };
    let paths = run(&dir, &mesh, &output, 100, 0.01);
    for (name, w, h) in [("theta.png", 1000, 600), ("energy.png", 1000, 850)] {
        let path = dir.join(name);
        assert!(paths.contains(&path));
        let (pw, ph, colours) = decode_png(&path);
        assert_eq!((pw, ph), (w, h), "{name}");
        assert!(colours > 20, "{name}: only {colours} distinct colours (blank?)");
    }
}

#[test]
fn frames_that_do_not_match_the_mesh_are_refused_naming_the_field() {
    let dir = common::scratch("mismatch");
    let mesh = plate_mesh(1, 2);
    let mut data = synthetic_frame(&mesh, 0, 0.01);
    data.von_mises.pop();
    let mut w = FrameWriters::new(&dir, &mesh, &all_outputs(), None).unwrap();
    let err = w.frame(&data.frame()).unwrap_err().to_string();
    assert!(
        err.contains("von_mises") && err.contains(&mesh.num_nodes().to_string()),
        "{err}"
    );
}

/// `(timestep, file)` of every DataSet in a .pvd.
fn pvd_entries(path: &Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.trim_end().ends_with("</VTKFile>"), "pvd not closed:\n{text}");
    text.lines()
        .filter(|l| l.contains("<DataSet"))
        .map(|l| {
            let attr = |name: &str| {
                let start = l.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
                l[start..start + l[start..].find('"').unwrap()].to_string()
            };
            (attr("timestep").parse().unwrap(), attr("file"))
        })
        .collect()
}

#[test]
fn pvd_lists_every_written_frame_with_its_time_and_each_vtu_is_complete() {
    let dir = common::scratch("pvd");
    let mesh = plate_mesh(2, 6);
    let output = Output {
        every: 5,
        plots: false,
        animation: false,
        viewer: false,
        ..all_outputs()
    };
    let dt = 0.004;
    let paths = run(&dir, &mesh, &output, 23, dt);
    let entries = pvd_entries(&dir.join("pendulum.pvd"));
    let steps = [0usize, 5, 10, 15, 20];
    assert_eq!(entries.len(), steps.len());
    for ((t, file), step) in entries.iter().zip(steps) {
        assert_eq!(*t, step as f64 * dt, "time of step {step}");
        assert_eq!(file, &format!("frames/step_{step:05}.vtu"));
        let vtu = dir.join(file);
        assert!(paths.contains(&vtu));
        let text = String::from_utf8_lossy(&std::fs::read(&vtu).unwrap()).into_owned();
        assert!(text.contains(&format!(r#"NumberOfPoints="{}""#, mesh.num_nodes())));
        for field in [
            "displacement_m",
            "velocity_m_s",
            "acceleration_m_s2",
            "von_mises_Pa",
            "cauchy_stress_Pa",
            "TimeValue",
            "theta_rad",
            "boundary_rotation",
        ] {
            assert!(text.contains(&format!(r#"Name="{field}""#)), "{file} lacks {field}");
        }
        assert!(
            text.contains(r#"compressor="vtkZLibDataCompressor""#),
            "{file} is not compressed"
        );
        assert!(text.trim_end().ends_with("</VTKFile>"));
    }
    assert_eq!(
        std::fs::read_dir(dir.join("frames")).unwrap().count(),
        steps.len(),
        "no partial files left"
    );
}

#[test]
fn pvd_is_valid_while_the_run_is_still_going() {
    let dir = common::scratch("pvd-early");
    let mesh = plate_mesh(1, 3);
    let output = Output {
        plots: false,
        animation: false,
        viewer: false,
        ..all_outputs()
    };
    let mut w = FrameWriters::new(&dir, &mesh, &output, None).unwrap();
    assert!(pvd_entries(&dir.join("pendulum.pvd")).is_empty());
    for step in 0..3 {
        w.frame(&synthetic_frame(&mesh, step, 0.01).frame()).unwrap();
        assert_eq!(pvd_entries(&dir.join("pendulum.pvd")).len(), step + 1);
    }
    drop(w); // the run "stops" without finish()
    assert_eq!(pvd_entries(&dir.join("pendulum.pvd")).len(), 3);
}

/// Reads every file with meshio and returns, per file, the points, every point and cell array and
/// the field data as JSON, each array as the hex of its little-endian Float64 bytes (exact).
fn meshio_dump(files: &[std::path::PathBuf]) -> Vec<serde_json::Value> {
    let script = r#"
import sys, json, meshio, numpy as np
h = lambda v: np.ascontiguousarray(np.asarray(v, dtype="<f8")).tobytes().hex()
for path in sys.argv[1:]:
    m = meshio.read(path)
    print(json.dumps({
        "points": h(m.points),
        "cells": {c.type: h(c.data) for c in m.cells},
        "point_data": {k: h(v) for k, v in m.point_data.items()},
        "cell_data": {k: h(np.concatenate(v)) for k, v in m.cell_data.items()},
        "field_data": {k: h(v) for k, v in m.field_data.items()},
    }))
"#;
    let out = std::process::Command::new("python3")
        .args(["-c", script])
        .args(files)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "meshio failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    text.lines().map(|l| serde_json::from_str(l).unwrap()).collect()
}

/// The Float64 values of one hex-encoded array of [`meshio_dump`].
fn floats(v: &serde_json::Value) -> Vec<f64> {
    let hex = v.as_str().unwrap_or_else(|| panic!("not an array dump: {v}"));
    (0..hex.len())
        .step_by(16)
        .map(|i| {
            let bytes: Vec<u8> = (i..i + 16)
                .step_by(2)
                .map(|j| u8::from_str_radix(&hex[j..j + 2], 16).unwrap())
                .collect();
            f64::from_le_bytes(bytes.try_into().unwrap())
        })
        .collect()
}

#[test]
fn meshio_reads_every_frame_back_with_equal_values() {
    if !tools::tool_or_skip(
        "meshio_reads_every_frame_back_with_equal_values",
        tools::python_module("meshio"),
        "python3 with meshio",
        "pip install meshio",
    ) {
        return;
    }
    let dir = common::scratch("meshio");
    let mesh = plate_mesh(2, 5);
    let output = Output {
        plots: false,
        animation: false,
        viewer: false,
        ..all_outputs()
    };
    let dt = 0.01;
    run(&dir, &mesh, &output, 2, dt);
    let files: Vec<_> = pvd_entries(&dir.join("pendulum.pvd"))
        .into_iter()
        .map(|(_, f)| dir.join(f))
        .collect();
    assert_eq!(files.len(), 3);
    let dumps = meshio_dump(&files);
    assert_eq!(dumps.len(), files.len());
    let as_f32 = |v: f64| v as f32 as f64;
    for (step, d) in dumps.iter().enumerate() {
        let expected = synthetic_frame(&mesh, step, dt);
        // Float64 arrays: bit-identical.
        let points: Vec<f64> = mesh.nodes.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
        assert_eq!(floats(&d["points"]), points, "step {step}: points");
        for (name, values) in [
            ("displacement_m", &expected.displacement),
            ("velocity_m_s", &expected.velocity),
            ("acceleration_m_s2", &expected.acceleration),
        ] {
            let v: Vec<f64> = values.iter().flat_map(|x| [x[0], x[1], 0.0]).collect();
            assert_eq!(floats(&d["point_data"][name]), v, "step {step}: {name}");
        }
        // Float32 stresses: equal to single precision (the stored value is the rounded one).
        let vm: Vec<f64> = expected.von_mises.iter().map(|&v| as_f32(v)).collect();
        assert_eq!(floats(&d["point_data"]["von_mises_Pa"]), vm, "step {step}: von Mises");
        let cauchy: Vec<f64> = expected
            .cauchy
            .iter()
            .flat_map(|s| [s[0], s[1], 0.0, s[2], 0.0, 0.0].map(as_f32))
            .collect();
        assert_eq!(
            floats(&d["point_data"]["cauchy_stress_Pa"]),
            cauchy,
            "step {step}: Cauchy"
        );
        let conn: Vec<f64> = mesh.triangles.iter().flatten().map(|&n| n as f64).collect();
        assert_eq!(floats(&d["cells"]["triangle6"]), conn, "step {step}: triangles");
        let hinge: f64 = floats(&d["cell_data"]["boundary_rotation"]).iter().sum();
        assert_eq!(
            hinge as usize,
            mesh.edges_named("rotation").count(),
            "hinge edges flagged"
        );
        assert_eq!(floats(&d["field_data"]["TimeValue"]), vec![step as f64 * dt]);
        assert_eq!(floats(&d["field_data"]["theta_rad"]), vec![expected.theta]);
    }
}

#[test]
fn default_runs_paraview_frames_are_at_most_a_third_of_the_uncompressed_size() {
    use pendulum_fem::commands::run::{run as run_job, RunOptions};
    // The size of one frame of the default run written as an uncompressed base64 VTU, the
    // reference of the ratio.
    const UNCOMPRESSED_FRAME_BYTES: u64 = 734_827;
    let dir = common::scratch("default-size");
    let mut config = pendulum_fem::Config::default();
    config.output.plots = false;
    config.output.animation = false;
    config.output.viewer = false;
    let opts = RunOptions {
        config,
        out: Some(dir.clone()),
        observers: vec![pendulum_fem::render::pictures::attach()],
        ..Default::default()
    };
    run_job(&opts).unwrap();
    let sizes: Vec<u64> = std::fs::read_dir(dir.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().metadata().unwrap().len())
        .collect();
    assert_eq!(sizes.len(), 26, "the default output.every = 4: steps 0, 4, …, 100");
    let total: u64 = sizes.iter().sum();
    let ratio = total as f64 / (sizes.len() as u64 * UNCOMPRESSED_FRAME_BYTES) as f64;
    eprintln!(
        "default run: {total} bytes in {} frames, {ratio:.3} of the uncompressed size",
        sizes.len()
    );
    assert!(ratio <= 1.0 / 3.0, "frames are {ratio:.3} of the uncompressed size");
}

#[test]
fn paraview_and_pictures_thin_separately_and_both_end_on_the_last_step() {
    let dir = common::scratch("thinning");
    let mesh = plate_mesh(1, 3);
    let output = Output {
        every: 7,
        paraview_every: Some(4),
        plots: false,
        viewer: false,
        ..all_outputs()
    };
    let dt = 0.01;
    let steps = 22;
    let mut w = FrameWriters::new(&dir, &mesh, &output, None).unwrap();
    let frames: Vec<_> = (0..=steps).map(|s| synthetic_frame(&mesh, s, dt)).collect();
    for f in &frames {
        w.frame(&f.frame()).unwrap();
    }
    w.last_frame(&frames[steps].frame()).unwrap();
    w.finish(&synthetic_history(steps, dt)).unwrap();
    let written: Vec<String> = pvd_entries(&dir.join("pendulum.pvd"))
        .into_iter()
        .map(|(_, f)| f)
        .collect();
    let expected: Vec<String> = [0, 4, 8, 12, 16, 20, 22]
        .iter()
        .map(|s| format!("frames/step_{s:05}.vtu"))
        .collect();
    assert_eq!(written, expected);
    let (gif_frames, _, _) = decode_gif(&dir.join("von_mises.gif"));
    assert_eq!(gif_frames, 5, "steps 0, 7, 14, 21 and the last, 22");
}

#[test]
fn a_run_whose_frames_would_exceed_a_gigabyte_is_warned_about_with_the_keys_to_change() {
    use pendulum_fem::render::pictures::output_size_warning;
    let mesh = pendulum_fem::mesh::generate(&pendulum_fem::Config::default()).unwrap();
    let mut cfg = pendulum_fem::Config::default();
    assert_eq!(
        output_size_warning(&cfg, &mesh),
        None,
        "the default run writes about 25 MB"
    );
    cfg.time.end = 50.0;
    cfg.output.every = 1;
    let w = output_size_warning(&cfg, &mesh).expect("5000 frames of 0.24 MB");
    assert!(w.contains("GB") && w.contains("output.paraview_every"), "{w}");
    cfg.output.paraview_every = Some(10);
    assert_eq!(output_size_warning(&cfg, &mesh), None, "500 frames are 0.12 GB");
}

#[test]
fn flags_off_write_no_files() {
    let dir = common::scratch("flags-off");
    let mesh = plate_mesh(1, 3);
    let output = Output {
        plots: false,
        animation: false,
        paraview: false,
        viewer: false,
        ..all_outputs()
    };
    let paths = run(&dir, &mesh, &output, 5, 0.01);
    assert!(paths.is_empty(), "{paths:?}");
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into())
        .collect();
    assert!(names.is_empty(), "{names:?}");
}

#[test]
fn each_flag_writes_exactly_its_files() {
    let all = [
        "theta.png",
        "energy.png",
        "displacement.gif",
        "von_mises.gif",
        "pendulum.pvd",
        "frames",
        "viewer.html",
    ];
    let mesh = plate_mesh(1, 3);
    for (flag, expected) in [
        ("plots", &["theta.png", "energy.png"][..]),
        ("animation", &["displacement.gif", "von_mises.gif"][..]),
        ("paraview", &["pendulum.pvd", "frames"][..]),
        ("viewer", &["viewer.html"][..]),
    ] {
        let dir = common::scratch(flag);
        let output = Output {
            plots: flag == "plots",
            animation: flag == "animation",
            paraview: flag == "paraview",
            viewer: flag == "viewer",
            ..all_outputs()
        };
        run(&dir, &mesh, &output, 4, 0.01);
        for name in all {
            assert_eq!(dir.join(name).exists(), expected.contains(&name), "{flag} on: {name}");
        }
    }
}

#[test]
fn fresh_run_folders_are_numbered_and_latest_points_to_the_newest() {
    let base = common::scratch("runs").join("results");
    let a = prepare_output_dir(&base, None, false).unwrap();
    let b = prepare_output_dir(&base, None, false).unwrap();
    assert_eq!(a, base.join("run-0001"));
    assert_eq!(b, base.join("run-0002"));
    std::fs::create_dir(base.join("run-0041")).unwrap();
    let c = prepare_output_dir(&base, None, false).unwrap();
    assert_eq!(c, base.join("run-0042"), "next after the largest number");
    let latest = base.join("latest");
    if let Ok(target) = std::fs::read_link(&latest) {
        assert_eq!(target, Path::new("run-0042"));
        assert_eq!(
            std::fs::canonicalize(&latest).unwrap(),
            std::fs::canonicalize(&c).unwrap()
        );
    } else {
        let text = std::fs::read_to_string(base.join("latest.txt")).unwrap();
        assert_eq!(text.trim(), "run-0042");
    }
    assert_eq!(std::fs::read_dir(&c).unwrap().count(), 0, "a fresh folder is empty");
}

#[test]
fn explicit_non_empty_folder_is_refused_without_force_and_left_untouched() {
    let dir = common::scratch("explicit");
    std::fs::write(dir.join("precious.txt"), "keep me").unwrap();
    let base = common::scratch("explicit-base");
    let err = prepare_output_dir(&base, Some(&dir), false).unwrap_err().to_string();
    assert!(err.contains(&dir.display().to_string()), "{err}");
    assert!(err.contains("--force"), "{err}");
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("precious.txt")]);
    assert_eq!(std::fs::read_to_string(dir.join("precious.txt")).unwrap(), "keep me");
    assert_eq!(
        std::fs::read_dir(&base).unwrap().count(),
        0,
        "no run folder made either"
    );

    assert_eq!(
        prepare_output_dir(&base, Some(&dir), true).unwrap(),
        dir,
        "--force lets it through"
    );
    assert_eq!(std::fs::read_to_string(dir.join("precious.txt")).unwrap(), "keep me");
}

#[test]
fn explicit_new_or_empty_folder_is_used_as_is() {
    let parent = common::scratch("explicit-new");
    let new = parent.join("a/b");
    assert_eq!(prepare_output_dir(Path::new("unused"), Some(&new), false).unwrap(), new);
    assert!(new.is_dir());
    assert_eq!(
        prepare_output_dir(Path::new("unused"), Some(&new), false).unwrap(),
        new,
        "empty is fine"
    );
    assert!(!Path::new("unused").exists());
}

#[test]
fn hundred_frames_of_a_1200_triangle_mesh_are_written_quickly() {
    use pendulum_fem::render::anim::{write_gif, AnimField, KeptFrame, KeptFrames, Scene};
    use pendulum_fem::render::plot::{write_energy_png, write_theta_png};
    use pendulum_fem::render::viewer::write_viewer;
    let dir = common::scratch("timing");
    let mesh = plate_mesh(4, 150);
    assert_eq!(mesh.triangles.len(), 1200);
    let steps = 99;
    let data: Vec<FrameData> = (0..=steps).map(|s| synthetic_frame(&mesh, s, 0.01)).collect();
    let clock = Instant::now();
    let mut kept = KeptFrames::new(200);
    for f in &data {
        kept.push(KeptFrame::from_frame(&mesh.nodes, &f.frame()));
    }
    let frames = kept.into_frames();
    let scene = Scene::new(&mesh.nodes, &frames, None, Some(0.12));
    let t_keep = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    write_gif(
        &dir.join("displacement.gif"),
        &mesh,
        &frames,
        AnimField::Displacement,
        &scene,
    )
    .unwrap();
    write_gif(&dir.join("von_mises.gif"), &mesh, &frames, AnimField::VonMises, &scene).unwrap();
    let t_gif = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let history = synthetic_history(steps, 0.01);
    write_theta_png(&dir.join("theta.png"), &history).unwrap();
    write_energy_png(&dir.join("energy.png"), &history).unwrap();
    let t_plot = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    write_viewer(
        &dir.join("viewer.html"),
        &mesh,
        &frames,
        &scene,
        Some(&history),
        "timing",
    )
    .unwrap();
    let t_viewer = clock.elapsed().as_secs_f64();
    eprintln!(
        "100 frames, 1200 triangles, {} nodes: keep {t_keep:.3} s, both GIFs {t_gif:.3} s, both plots {t_plot:.3} s, \
         viewer {t_viewer:.3} s",
        mesh.num_nodes()
    );
    let (n, _, _) = decode_gif(&dir.join("displacement.gif"));
    assert_eq!(n, 100);
    if !cfg!(debug_assertions) {
        assert!(t_gif < 3.0, "GIFs took {t_gif} s");
        assert!(t_plot + t_viewer < 3.0, "plots + viewer took {} s", t_plot + t_viewer);
    }
}
