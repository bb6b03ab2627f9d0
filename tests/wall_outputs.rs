//! The outputs of a run with a rigid wall (issue 10): the plots mark the impacts, the animations
//! and the viewer draw the wall, the ParaView frames carry the contact pressure and the wall is a
//! block of its own; a run without a wall writes none of it.
//!
//! One claim, the wall in every output, past 600 lines because each output is checked in a test
//! of its own.

use crate::common;
use common::tools;
use common::Extremes;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;

use pendulum_fem::commands::run::{run as run_job, RunOptions, RunSummary};
use pendulum_fem::config::WallKind;
use pendulum_fem::render::anim::{WALL_FILL, WALL_HATCH};
use pendulum_fem::render::plot::{History, IMPACT_RGB};
use pendulum_fem::run::rows::{read_events, read_records};
use pendulum_fem::Config;

/// The run driver's options for `config` into the folder `dir`, quiet.
fn options(config: Config, dir: &Path) -> RunOptions {
    RunOptions {
        config,
        out: Some(dir.to_path_buf()),
        force: true,
        observers: vec![pendulum_fem::render::pictures::attach()],
        ..Default::default()
    }
}

/// A run of `end` seconds into a fresh folder, with or without the rigid wall, and its summary.
fn run_case(name: &str, wall: bool, end: f64) -> (PathBuf, RunSummary) {
    let dir = common::scratch(name);
    let mut config = Config::default();
    if wall {
        config.wall.kind = WallKind::Rigid;
    }
    config.time.end = end;
    // every step a frame: the frames are compared with the steps inside and outside the impacts
    config.output.every = 1;
    let summary = run_job(&options(config, &dir)).unwrap();
    (dir, summary)
}

/// A run of the configuration `toml` (a case of the random-case campaign) into a fresh folder
/// `name`, and its outcome.
fn run_toml(name: &str, toml: &str) -> (PathBuf, Result<RunSummary, pendulum_fem::Error>) {
    let config = Config::from_toml_str(toml).unwrap();
    let dir = common::scratch(name);
    let outcome = run_job(&options(config, &dir));
    (dir, outcome)
}

/// The wall run shared by the tests and its summary: three impacts (about 0.240, 0.721 and
/// 1.202 s).
fn wall_job() -> &'static (PathBuf, RunSummary) {
    static JOB: OnceLock<(PathBuf, RunSummary)> = OnceLock::new();
    JOB.get_or_init(|| run_case("wall-run", true, 1.25))
}

/// The folder of the wall run.
fn wall_run() -> &'static Path {
    &wall_job().0
}

/// A run without a wall over the same time.
fn plain_run() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| run_case("plain-run", false, 1.25).0)
}

/// The `(start, end)` of the impacts in the run's `events.csv`.
fn impacts(dir: &Path) -> Vec<(f64, f64)> {
    let mut h = History::of_records(&read_records(&dir.join("results.csv")).unwrap());
    h.set_impacts(&read_events(&dir.join("events.csv")).unwrap());
    h.impacts
}

/// Width, height and RGB pixels of a PNG.
fn png_rgb(path: &Path) -> (usize, usize, Vec<[u8; 3]>) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let px = buf[..info.buffer_size()]
        .chunks(channels)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    (info.width as usize, info.height as usize, px)
}

/// The columns holding at least `min` pixels of `rgb`, grouped into runs of adjacent columns:
/// the centre of each run.
fn column_groups(path: &Path, rgb: (u8, u8, u8), min: usize) -> Vec<f64> {
    let (w, h, px) = png_rgb(path);
    let target = [rgb.0, rgb.1, rgb.2];
    let columns: Vec<usize> = (0..w)
        .filter(|&x| (0..h).filter(|&y| px[y * w + x] == target).count() >= min)
        .collect();
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for x in columns {
        match groups.last_mut() {
            Some(g) if x - *g.last().unwrap() <= 1 => g.push(x),
            _ => groups.push(vec![x]),
        }
    }
    groups
        .iter()
        .map(|g| g.iter().sum::<usize>() as f64 / g.len() as f64)
        .collect()
}

#[test]
fn theta_png_marks_each_impact_of_events_csv_at_its_time() {
    let dir = wall_run();
    let spans = impacts(dir);
    assert_eq!(spans.len(), 3, "{spans:?}");
    // the marks are vertical lines over the whole plot (hundreds of pixels of the mark colour)
    let xs = column_groups(&dir.join("theta.png"), IMPACT_RGB, 200);
    assert_eq!(xs.len(), 3, "mark columns {xs:?}");
    // x is linear in t: the middle mark sits where the middle impact starts
    let (t, x) = ([spans[0].0, spans[1].0, spans[2].0], xs);
    let expected = (t[1] - t[0]) / (t[2] - t[0]);
    let drawn = (x[1] - x[0]) / (x[2] - x[0]);
    assert!((drawn - expected).abs() < 0.01, "marks at {x:?} for impacts at {t:?}");
    // and the time axis they give runs from t = 0 at the plot's left edge to time.end at its right
    let b = (x[2] - x[0]) / (t[2] - t[0]);
    let a = x[0] - b * t[0];
    assert!(
        (50.0..150.0).contains(&a) && (900.0..1000.0).contains(&(a + 1.25 * b)),
        "{x:?}: {a} + {b} t"
    );
    // the energy plot marks them too
    let ys = column_groups(&dir.join("energy.png"), IMPACT_RGB, 200);
    assert_eq!(ys.len(), 3, "energy.png mark columns {ys:?}");
}

#[test]
fn plots_without_a_wall_have_no_impact_marks_and_no_contact_curve() {
    let dir = plain_run();
    assert!(!dir.join("events.csv").exists());
    for name in ["theta.png", "energy.png"] {
        let (_, _, px) = png_rgb(&dir.join(name));
        let target = [IMPACT_RGB.0, IMPACT_RGB.1, IMPACT_RGB.2];
        assert_eq!(px.iter().filter(|p| **p == target).count(), 0, "{name}");
    }
    let h = History::of_records(&read_records(&dir.join("results.csv")).unwrap());
    assert!(!h.has_wall());
    assert_eq!(h.energy_curves().len(), 3);
}

#[test]
fn energy_plot_of_a_wall_run_has_the_contact_energy_rising_during_each_impact() {
    let dir = wall_run();
    let mut h = History::of_records(&read_records(&dir.join("results.csv")).unwrap());
    h.set_impacts(&read_events(&dir.join("events.csv")).unwrap());
    assert!(h.has_wall());
    let curves = h.energy_curves();
    let (name, contact) = curves.last().unwrap();
    assert_eq!(*name, "contact (part of the total)");
    for (i, (&t, &e)) in h.time.iter().zip(contact).enumerate() {
        let inside = h.impacts.iter().any(|&(a, b)| (a..=b).contains(&t));
        assert_eq!(e > 0.0, inside, "row {i}: t = {t}, contact energy {e}");
    }
    assert!(
        contact.iter().any(|&e| e > 1e-3),
        "the contact energy shows on the plot's scale"
    );
}

/// The frames of a GIF, composed (each frame drawn over the one before), as palette indices.
fn gif_frames(path: &Path) -> (usize, usize, Vec<Vec<u8>>) {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::Indexed);
    let mut dec = opts.read_info(std::fs::File::open(path).unwrap()).unwrap();
    let (w, h) = (dec.width() as usize, dec.height() as usize);
    let mut canvas = vec![0u8; w * h];
    let mut frames = Vec::new();
    while let Some(f) = dec.read_next_frame().unwrap() {
        let (l, t, fw) = (f.left as usize, f.top as usize, f.width as usize);
        for (k, &p) in f.buffer.iter().enumerate() {
            canvas[(t + k / fw) * w + l + k % fw] = p;
        }
        frames.push(canvas.clone());
    }
    (w, h, frames)
}

/// Writes palette-index pixels as an RGB PNG with the GIF's own palette (to look at a frame).
fn save_frame(path: &Path, gif_path: &Path, w: usize, h: usize, px: &[u8]) {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::Indexed);
    let dec = opts.read_info(std::fs::File::open(gif_path).unwrap()).unwrap();
    let palette = dec.global_palette().unwrap().to_vec();
    let rgb: Vec<u8> = px
        .iter()
        .flat_map(|&i| palette[3 * i as usize..3 * i as usize + 3].to_vec())
        .collect();
    let mut enc = png::Encoder::new(std::fs::File::create(path).unwrap(), w as u32, h as u32);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().unwrap().write_image_data(&rgb).unwrap();
}

/// The columns (in rows 70 to 580 of the picture area) entirely of the wall's colours.
fn wall_columns(w: usize, px: &[u8]) -> Vec<usize> {
    (0..w)
        .filter(|&x| (70..580).all(|y| [WALL_FILL, WALL_HATCH].contains(&px[y * w + x])))
        .collect()
}

#[test]
fn gif_frames_draw_the_wall_as_a_hatched_band_left_of_the_face_that_the_head_reaches() {
    let dir = wall_run();
    for name in ["displacement.gif", "von_mises.gif"] {
        let path = dir.join(name);
        let (w, h, frames) = gif_frames(&path);
        assert_eq!(frames.len(), 126, "{name}");
        if let Some(out) = std::env::var_os("WALL_FRAME_PNG") {
            for i in [0, 24] {
                save_frame(
                    &Path::new(&out).join(format!("{name}.frame{i}.png")),
                    &path,
                    w,
                    h,
                    &frames[i],
                );
            }
        }
        for (i, px) in frames.iter().enumerate() {
            let band = wall_columns(w, px);
            // from the left edge of the picture area (x = 12) to the face, about 30 px wide
            assert!(band.len() >= 15, "{name} frame {i}: wall columns {band:?}");
            assert_eq!(
                band[0], 13,
                "{name} frame {i}: the band starts at the picture area's edge"
            );
            assert!(band.windows(2).all(|c| c[1] == c[0] + 1), "{name} frame {i}: one band");
            // hatched: both colours
            let left: Vec<u8> = (70..580)
                .flat_map(|y| px[y * w + 13..y * w + band[band.len() - 1]].to_vec())
                .collect();
            assert!(
                left.contains(&WALL_FILL) && left.contains(&WALL_HATCH),
                "{name} frame {i}"
            );
        }
        // the head (colour-map pixels, indices below 200) comes up to the face at the impact
        // (t = 0.24 s, frame 24) and is far from it at the release (frame 0); within 12 px, as the
        // magnified elastic part draws the compressed head a few pixels off the face

        let face = *wall_columns(w, &frames[0]).last().unwrap();
        let nearest = |px: &[u8]| {
            (70..580)
                .flat_map(|y| (face + 1..w).filter(move |&x| px[y * w + x] < 200))
                .min()
                .unwrap()
        };
        assert!(
            nearest(&frames[24]) <= face + 12,
            "{name}: head at {} px, face at {face}",
            nearest(&frames[24])
        );
        assert!(
            nearest(&frames[0]) > face + 60,
            "{name}: head at {} px at the release",
            nearest(&frames[0])
        );
        if let Some(out) = std::env::var_os("WALL_FRAME_PNG") {
            save_frame(
                &Path::new(&out).join(format!("{name}.frame24.png")),
                &path,
                w,
                h,
                &frames[24],
            );
        }
    }
    // no wall: no band
    let (w, _, frames) = gif_frames(&plain_run().join("displacement.gif"));
    assert!(frames.iter().all(|px| wall_columns(w, px).is_empty()));
}

/// `contact_pressure_Pa` (maximum), time and the point field names of each frame, read with meshio.
fn meshio_pressures(files: &[PathBuf]) -> Vec<(f64, f64, Vec<String>)> {
    let script = r#"
import sys, json, meshio, numpy as np
for path in sys.argv[1:]:
    m = meshio.read(path)
    p = m.point_data.get("contact_pressure_Pa")
    print(json.dumps([float(p.max()) if p is not None else -1.0, float(np.ravel(m.field_data["TimeValue"])[0]), sorted(m.point_data)]))
"#;
    let out = Command::new("python3")
        .args(["-c", script])
        .args(files)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "meshio failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn frame_files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    v.sort();
    v
}

#[test]
fn vtu_contact_pressure_is_non_zero_exactly_in_the_frames_inside_an_impact() {
    if !tools::tool_or_skip(
        "vtu_contact_pressure_is_non_zero_exactly_in_the_frames_inside_an_impact",
        tools::python_module("meshio"),
        "python3 with meshio",
        "pip install meshio",
    ) {
        return;
    }
    let dir = wall_run();
    let spans = impacts(dir);
    let frames = meshio_pressures(&frame_files(dir));
    assert_eq!(frames.len(), 126);
    let mut in_contact = 0;
    for (p, t, _) in &frames {
        let inside = spans.iter().any(|&(a, b)| (a..=b).contains(t));
        // k · max(−gap, 0): 2e10 N/m³ × up to 0.4 mm, a few MPa
        assert_eq!(*p > 0.0, inside, "t = {t}: pressure {p} Pa");
        assert!(*p >= 0.0 && *p < 2e10 * 1e-3, "t = {t}: {p} Pa");
        in_contact += usize::from(inside);
    }
    assert_eq!(
        in_contact, 1,
        "the frame at 0.24 s lies inside the first impact (0.2395 to 0.2417 s)"
    );
    // the wall is a second block of every time step: wall.vtu, a quad whose right edge is the face
    let pvd = std::fs::read_to_string(dir.join("pendulum.pvd")).unwrap();
    assert_eq!(pvd.matches(r#"part="1" file="wall.vtu""#).count(), 126);
    assert_eq!(pvd.matches(r#"part="0" file="frames/"#).count(), 126);
    let script = r#"
import meshio, sys
m = meshio.read(sys.argv[1])
print(m.cells[0].type, m.points[:, 0].min(), m.points[:, 0].max())
"#;
    let out = Command::new("python3")
        .args(["-c", script])
        .arg(dir.join("wall.vtu"))
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    let words: Vec<&str> = text.split_whitespace().collect();
    assert_eq!(words[0], "quad", "{text}");
    assert_eq!(words[2].parse::<f64>().unwrap(), -0.06, "{text}");
    assert!(words[1].parse::<f64>().unwrap() < -0.06, "{text}");
    // without a wall: no pressure field, no wall block
    let plain = plain_run();
    let frames = meshio_pressures(&frame_files(plain)[..3]);
    assert!(frames
        .iter()
        .all(|(p, _, names)| *p == -1.0 && !names.iter().any(|n| n.contains("contact"))));
    assert!(!plain.join("wall.vtu").exists());
    assert!(!std::fs::read_to_string(plain.join("pendulum.pvd"))
        .unwrap()
        .contains("part=\"1\""));
}

/// The JSON embedded in a viewer page.
fn embedded_json(html: &str) -> serde_json::Value {
    let start = html.find(r#"type="application/json">"#).unwrap() + r#"type="application/json">"#.len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end].replace("<\\/", "</")).unwrap()
}

#[test]
fn viewer_carries_the_wall_and_the_impacts_and_draws_them_in_chromium() {
    let dir = wall_run();
    let html = std::fs::read_to_string(dir.join("viewer.html")).unwrap();
    let data = embedded_json(&html);
    assert_eq!(data["wall_x"], -0.06);
    assert_eq!(data["wall"]["face_x"], -0.06);
    let spans = data["impacts"].as_array().unwrap();
    assert_eq!(spans.len(), 3, "{}", data["impacts"]);
    assert!(html.contains("function drawWall"));
    let plain = embedded_json(&std::fs::read_to_string(plain_run().join("viewer.html")).unwrap());
    assert!(plain["wall_x"].is_null() && plain.get("wall").is_none() && plain.get("impacts").is_none());

    let test = "viewer_carries_the_wall_and_the_impacts_and_draws_them_in_chromium";
    let Some(chrome) = tools::chromium(test) else {
        return;
    };
    let url = format!(
        "file://{}",
        std::fs::canonicalize(dir.join("viewer.html")).unwrap().display()
    );
    let dom = tools::run_chromium(&chrome, &["--dump-dom".into(), format!("{url}#selftest")]);
    assert!(
        dom.contains("<title>SELFTEST PASS</title>"),
        "the wall viewer's self-test failed"
    );
    let shot = dir.join("viewer.png");
    tools::run_chromium(
        &chrome,
        &[
            "--window-size=1300,800".into(),
            format!("--screenshot={}", shot.display()),
            url,
        ],
    );
    // the wall's face line (#555) and the impact lines (#9467bd) are on the page
    let (_, _, px) = png_rgb(&shot);
    let count = |c: [u8; 3]| px.iter().filter(|p| **p == c).count();
    assert!(
        count([0x55, 0x55, 0x55]) > 200,
        "face line pixels: {}",
        count([0x55, 0x55, 0x55])
    );
    assert!(
        count([0x94, 0x67, 0xbd]) > 100,
        "impact line pixels: {}",
        count([0x94, 0x67, 0xbd])
    );
    if let Some(out) = std::env::var_os("WALL_FRAME_PNG") {
        std::fs::copy(&shot, Path::new(&out).join("viewer.png")).unwrap();
    }
}

#[test]
fn a_wall_runs_csv_files_write_no_negative_zero() {
    // the contact force is a sum of clamped terms, −0.0 whenever the head is off the wall: most rows
    let dir = wall_run();
    let mut zeros = 0;
    for file in ["results.csv", "events.csv"] {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        for (k, line) in text.lines().enumerate().skip(1) {
            for cell in line.split(',') {
                assert!(
                    !cell.starts_with("-0") || cell.parse::<f64>().is_ok_and(|v| v != 0.0),
                    "{file} line {}: a negative zero `{cell}` in `{line}`",
                    k + 1
                );
                zeros += usize::from(cell == "0");
            }
        }
    }
    // the claim is about zeros that are written: there are many (off the wall, the force is 0)
    assert!(
        zeros > 100,
        "only {zeros} zero cells: the run is not the one this test is about"
    );
}

/// The rows of `events.csv`: (time, event, omega).
fn events(dir: &Path) -> Vec<(f64, String, f64)> {
    let text = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[0].parse().unwrap(), c[1].to_string(), c[3].parse().unwrap())
        })
        .collect()
}

#[test]
fn a_wall_runs_summary_reports_impacts_not_a_period() {
    let (dir, summary) = wall_job();
    let impacts = summary.impacts.expect("a run with a wall reports its impacts");
    let rows = events(dir);
    let starts: Vec<f64> = rows.iter().filter(|r| r.1 == "impact_start").map(|r| r.0).collect();
    assert_eq!((impacts.count, starts.len()), (3, 3), "{rows:?}");
    // the figures are those of events.csv (its numbers read back bit for bit)
    let interval = (starts[2] - starts[0]) / 2.0;
    assert_eq!(impacts.mean_interval, Some(interval));
    let e: Vec<f64> = rows
        .windows(2)
        .filter(|w| w[0].1 == "impact_start")
        .map(|w| (w[1].2 / w[0].2).abs())
        .collect();
    let mean = e.iter().sum::<f64>() / e.len() as f64;
    assert!(
        (impacts.restitution.unwrap() - mean).abs() < 1e-15,
        "{impacts:?} vs {e:?}"
    );
    // the energy-consistent contact returns the swing's energy to it but the part left in elastic
    // vibration (rebound 19.9996° of 20°, docs/src/contact.md), so the swing's e is 1 to 1e-5; the proxy rate ω
    // at the impact's end carries that vibration too: within 5e-3 of 1
    assert!((mean - 1.0).abs() < 5e-3, "restitution {mean}");
    // the rebound: 19.9996° for the converged reference (docs/src/contact.md); the records at dt = 0.01 s
    // sample the peak up to Δt/2 from it, ½ |α| (Δt/2)² = 0.0105° below (|α| = ω₀² sin 20° =
    // 14.7 rad/s², ω₀ = 2π/0.958 s), never above it
    let rebound = impacts.rebound_angle.unwrap().to_degrees();
    assert!(
        (19.9996 - 0.0106..19.9996 + 1e-4).contains(&rebound),
        "rebound {rebound}°"
    );
    // half a swing between impacts (0.4806 s of the 0.96 s period): no zero-crossing period there
    assert!((interval - 0.4806).abs() < 1e-3, "interval {interval}");
    // θ crosses zero only inside the ~2 ms impacts: the summary (and a sweep's period_s) has no period
    assert_eq!(summary.period, None, "a wall run's zero-crossing period");
}

#[test]
fn the_cli_summary_of_a_wall_run_prints_impacts_and_no_zero_crossing_period() {
    let run = |name: &str, wall: bool| {
        let dir = common::scratch(name);
        let mut cmd = common::bin();
        cmd.args(["run", "--force", "--set", "time.end=0.75", "--out"])
            .arg(&dir);
        for key in ["plots", "animation", "paraview", "viewer"] {
            cmd.args(["--set", &format!("output.{key}=false")]);
        }
        if wall {
            cmd.args(["--set", "wall.kind=\"rigid\""]);
        }
        let out = cmd.stderr(Stdio::inherit()).output().unwrap();
        assert!(out.status.success());
        String::from_utf8(out.stdout).unwrap()
    };
    let text = run("summary-wall", true);
    assert!(!text.contains("period estimate"), "{text}");
    assert!(text.contains("impacts            2, one every 0.48"), "{text}");
    assert!(
        text.contains("restitution        0.99") || text.contains("restitution        1.00"),
        "{text}"
    );
    assert!(text.contains("rebound to 19.99"), "{text}");
    // without a wall: the period, and no impacts
    let text = run("summary-plain", false);
    assert!(
        text.contains("period estimate") && !text.contains("impacts  "),
        "{text}"
    );
}

#[test]
fn an_observer_takes_the_rows_of_results_csv_and_impacts_csv_in_time_order() {
    use pendulum_fem::run::driver::{Attach, RunObserver};
    use pendulum_fem::run::rows::csv_values;
    use pendulum_fem::simulation::{Simulation, StepRecord};
    use std::sync::{Arc, Mutex};
    /// The values of the records an observer took, in the order it took them.
    struct Taken(Arc<Mutex<Vec<Vec<f64>>>>);
    impl RunObserver for Taken {
        fn record(&mut self, _: &mut Simulation, r: &StepRecord, _: bool) -> Result<(), pendulum_fem::Error> {
            self.0.lock().unwrap().push(csv_values(r));
            Ok(())
        }
        fn substeps(&mut self, records: &[StepRecord]) -> Result<(), pendulum_fem::Error> {
            self.0.lock().unwrap().extend(records.iter().map(csv_values));
            Ok(())
        }
        fn finish(self: Box<Self>, _: &mut Simulation, _: &StepRecord) -> Result<Vec<PathBuf>, pendulum_fem::Error> {
            Ok(Vec::new())
        }
    }
    let dir = common::scratch("observed-impact");
    let mut config = Config::default();
    config.wall.kind = WallKind::Rigid;
    config.time.end = 0.3;
    let taken = Arc::new(Mutex::new(Vec::new()));
    let to = Arc::clone(&taken);
    let opts = RunOptions {
        observers: vec![Attach::new(move |_| {
            Ok(Some(Box::new(Taken(Arc::clone(&to))) as Box<dyn RunObserver>))
        })],
        ..options(config, &dir)
    };
    run_job(&opts).unwrap();
    let rows = |name: &str| pendulum_fem::store::Table::read(&dir.join(name)).unwrap().rows;
    let (results, impacts) = (rows("results.csv"), rows("impacts.csv"));
    assert!(
        impacts.len() >= 20,
        "{} sub-step rows in the first impact",
        impacts.len()
    );
    let mut files: Vec<Vec<f64>> = results.into_iter().chain(impacts).collect();
    files.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let taken = taken.lock().unwrap();
    assert!(
        taken.windows(2).all(|w| w[0][0] < w[1][0]),
        "the records come in time order"
    );
    assert!(
        *taken == files,
        "the observer took every row of both files, bit for bit"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_impact_is_resolved_in_impacts_csv_so_identical_impacts_look_identical() {
    let dir = wall_run();
    let head = |p: &Path| std::fs::read_to_string(p).unwrap().lines().next().unwrap().to_string();
    let sub = dir.join("impacts.csv");
    assert_eq!(
        head(&sub),
        head(&dir.join("results.csv")),
        "impacts.csv has the columns of results.csv"
    );
    let h = History::of_records(&read_records(&sub).unwrap());
    let spans = impacts(dir);
    assert_eq!(spans.len(), 3, "{spans:?}");
    let mut peaks = Vec::new();
    for &(start, end) in &spans {
        let inside: Vec<usize> = (0..h.time.len())
            .filter(|&i| h.time[i] >= start && h.time[i] <= end)
            .collect();
        // sub-steps of τ/10 = 72 µs over an impact of 2.1 ms (docs/src/contact.md): about 29 rows
        assert!(
            inside.len() >= 20,
            "{} sub-step rows in the impact {start}–{end}",
            inside.len()
        );
        peaks.push(inside.iter().map(|&i| h.contact[i]).max_of());
    }
    // the three impacts are the same blow (rebound 19.9996° each): their peak contact energies,
    // sampled every 72 µs over a 2.1 ms pulse, agree to the sampling of a smooth peak,
    // about (π²/8)(72/2100)² = 1.4e-3; 1 % allows for the pulse's shape
    let largest = peaks.iter().cloned().max_of();
    for p in &peaks {
        assert!((p - largest).abs() < 0.01 * largest, "peak contact energies {peaks:?}");
    }
}

#[test]
fn energy_png_draws_identical_impacts_identically_and_overlays_them_on_their_own_time_scale() {
    let dir = wall_run();
    let path = dir.join("energy.png");
    let (w, h, px) = png_rgb(&path);
    let px = &px;
    let count = |x: usize, rows: std::ops::Range<usize>, rgb: [u8; 3]| rows.filter(|&y| px[y * w + x] == rgb).count();
    let (red, orange) = ([214, 39, 40], [255, 127, 14]);
    // the panels' rows (figure of 1000 × 1190 px: title, upper panel to about 500, strain panel
    // to about 850, impact panel below)
    assert_eq!((w, h), (1000, 1190));
    let (upper, strain, closeup) = (60..500, 520..850, 860..h);
    let marks = column_groups(&path, IMPACT_RGB, 200);
    assert_eq!(marks.len(), 3, "impact marks at {marks:?}");
    // the extent of a colour in the columns around each mark
    let extent = |x: f64, rows: std::ops::Range<usize>, rgb: [u8; 3]| {
        let ys: Vec<usize> = (x as usize - 5..=x as usize + 5)
            .flat_map(|c| rows.clone().filter(move |&y| px[y * w + c] == rgb))
            .collect();
        (*ys.iter().min().unwrap(), *ys.iter().max().unwrap())
    };
    // the contact energy's spike: the peaks in impacts.csv agree to 1e-3 (0.1157 J), less than a
    // pixel, so every spike runs between the same two rows, over 100 px (0 to 0.116 J)
    let spikes: Vec<(usize, usize)> = marks.iter().map(|&x| extent(x, upper.clone(), red)).collect();
    for s in &spikes {
        assert_eq!(*s, spikes[0], "contact spikes between rows {spikes:?}");
    }
    assert!(spikes[0].1 - spikes[0].0 > 100, "{spikes:?}");
    // the strain energy's peaks differ by up to 3 % in impacts.csv (its ringing sampled every
    // 72 µs): each spike reaches at least 95 % of the tallest one's height above the baseline
    let base = (strain.start..strain.end)
        .max_by_key(|&y| (0..w).filter(|&c| px[y * w + c] == orange).count())
        .unwrap();
    let heights: Vec<f64> = marks
        .iter()
        .map(|&x| (base - extent(x, strain.clone(), orange).0) as f64)
        .collect();
    let tallest = heights.iter().cloned().max_of();
    assert!(
        tallest > 150.0 && heights.iter().all(|&v| v >= 0.95 * tallest),
        "strain spikes {heights:?} px"
    );
    // the impact panel: the contact energy over most of its width, the three impacts on one
    // curve (a 2 px line drawn three times where they coincide: at most 6 px in any column,
    // where the curve is steep)
    let columns: Vec<usize> = (0..w).map(|x| count(x, closeup.clone(), red)).collect();
    let drawn: Vec<usize> = columns.iter().copied().filter(|&n| n > 0).collect();
    assert!(drawn.len() > 600, "the contact curve over {} columns", drawn.len());
    let mut sorted = drawn.clone();
    sorted.sort();
    assert!(
        sorted[sorted.len() / 2] <= 4,
        "median thickness {} px",
        sorted[sorted.len() / 2]
    );
}

#[test]
fn a_head_swung_over_the_pivot_passes_behind_the_deformable_block_and_stops_where_it_comes_round_onto_it() {
    // thrown over the pivot at 15 rad/s, the head comes down on the block's far side, 0.1 m
    // behind its face and 5 mm above its top end: it bounced off the face's line continued
    // there (ω from +12.7 to −9.4 rad/s at θ = 4.93 rad, 1.3 J of strain), with no contact event
    let dir = common::scratch("round-the-block");
    let mut config = Config::default();
    config.wall.kind = WallKind::Deformable;
    config.initial.angular_velocity = 15.0;
    config.time.end = 0.6;
    let message = run_job(&options(config, &dir))
        .expect_err("it comes round onto the block")
        .to_string();
    assert!(
        message.contains("outside the model") && message.contains("come round the face's end"),
        "{message}"
    );
    let history = History::of_records(&read_records(&dir.join("results.csv")).unwrap());
    let (t, theta) = (&history.time, &history.theta);
    // it passes the far side unhindered: θ rises through 3π/2 to the step before the error
    let last = *t.last().unwrap();
    assert!(last >= 0.49, "results up to {last} s");
    assert!(theta.windows(2).all(|w| w[1] > w[0]), "θ never turns back: {theta:?}");
    assert!(*theta.last().unwrap() > 5.0, "{}", theta.last().unwrap());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_head_coming_round_the_blocks_face_end_in_a_step_that_succeeds_stops_before_it_bounces_off_the_corner() {
    // seed 20's case 4 of the random-case campaign (tests/robustness.rs): a steel-like head swung
    // over the pivot comes down behind the face's line beyond its end. Every step succeeded: the
    // face's energy at its end pushed the head back (ω from +16.3 to −18.8 rad/s at θ = 4.31 rad,
    // "impact" from t = 1.2801 s, 16 mm deep) off a corner the model does not have
    let (dir, outcome) = run_toml(
        "round-the-corner",
        "[geometry]\nrod_half_width = 0.0141\nhead_radius = 0.05684\nhole_radius = 0.02502\n\
         head_center_distance = 0.1292\nthickness = 0.005873\n[mesh]\nrefine = 1.435\n\
         [material]\nyoungs_modulus = 1.509e11\npoisson_ratio = 0.422\ndensity = 7469\n\
         [initial]\nangle_deg = 169.9\nangular_velocity = 3.786\n[time]\ndt = 1.803e-2\nend = 1.3\n\
         [torque]\nprofile = \"sine\"\namplitude = -0.6444\nfrequency = 0.423\n\
         [wall]\nkind = \"deformable\"\nx = -0.07167\nyoungs_modulus = 8.141e10\ncenter_y = -0.1292\n\
         [contact]\nstiffness = 1.693e9\n",
    );
    let message = outcome.expect_err("it comes round the face's end").to_string();
    assert!(
        message.contains("outside the model") && message.contains("over the step") && message.contains("come round"),
        "{message}"
    );
    let history = History::of_records(&read_records(&dir.join("results.csv")).unwrap());
    let last = *history.time.last().unwrap();
    // the step before the one that came round is the last row, before the bogus bounce
    assert!((1.2..1.2801).contains(&last), "results up to {last} s");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_soft_head_struck_against_a_stiff_wall_comes_through_its_impact_without_a_cut_back() {
    // seed 18's case 5 of the random-case campaign (tests/robustness.rs) up to the end of its first
    // impact (0.3828 to 0.4007 s): a soft head (E = 3 MPa) against a stiff contact
    // (k = 1.6e12 N/m³), whose sub-steps need many Newton iterations each (slow contractions
    // while contact points change state): the default allowance of iterations takes them
    // without halving the step
    let toml = "[geometry]\nrod_half_width = 0.01549\nhead_radius = 0.05923\nhole_radius = 0.03029\n\
         head_center_distance = 0.1533\nthickness = 0.01409\n[mesh]\nrefine = 1.244\n\
         [material]\nyoungs_modulus = 2.983e6\npoisson_ratio = 0.3693\ndensity = 2458\n\
         [initial]\nangle_deg = 110.8\nangular_velocity = 5.128\n[time]\ndt = 1.672e-3\nend = 0.41\n\
         [torque]\nprofile = \"step\"\namplitude = 0.1059\nstart = 0.2837\n\
         [wall]\nkind = \"rigid\"\nx = -0.05963\n[contact]\nstiffness = 1.617e12\n\
         [output]\nplots = false\nanimation = false\nparaview = false\nviewer = false\n";
    let config = Config::from_toml_str(toml).unwrap();
    assert_eq!(config.solver.max_iterations, 40, "the default under test");
    let (dir, outcome) = run_toml("soft-head-stiff-wall", toml);
    let summary = outcome.unwrap();
    assert_eq!(summary.cutbacks, 0, "no sub-step was halved");
    let events = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    let kinds: Vec<&str> = events.lines().skip(1).filter_map(|l| l.split(',').nth(1)).collect();
    assert_eq!(kinds, ["impact_start", "impact_end"], "one impact, over: {events}");
    // the campaign's bar on the energy balance
    assert!(summary.energy_error < 1e-6, "energy error {:e}", summary.energy_error);
    let _ = std::fs::remove_dir_all(&dir);
}
