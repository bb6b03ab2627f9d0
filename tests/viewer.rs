//! The HTML viewer: one self-contained file that draws and responds to its controls, checked in
//! headless Chromium (`.ci/run` installs it; elsewhere the browser tests skip with a visible
//! warning, and fail when `CI` is set).

use crate::common;
use common::{plate, tools};

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use pendulum_fem::config::Output;
use plate::*;

/// The plate of the viewer tests: `NX × NY` rectangles, steps of `DT` \[s\].
const NX: usize = 2;
const NY: usize = 10;
const DT: f64 = 0.01;

/// Writes a viewer for a 30-step swing and returns its path.
fn viewer_file(name: &str) -> (PathBuf, usize) {
    let dir = common::scratch(name);
    let mesh = plate_mesh(NX, NY);
    let output = Output {
        plots: false,
        animation: false,
        paraview: false,
        ..all_outputs()
    };
    run(&dir, &mesh, &output, 30, DT);
    (dir.join("viewer.html"), mesh.triangles.len())
}

fn embedded_json(html: &str) -> serde_json::Value {
    let open = r#"<script id="pendulum-data" type="application/json">"#;
    let start = html.find(open).expect("data element") + open.len();
    let end = start + html[start..].find("</script>").expect("end of data");
    serde_json::from_str(&html[start..end]).expect("embedded data is JSON")
}

#[test]
fn viewer_is_one_self_contained_file_with_the_kept_frames_embedded() {
    let (path, triangles) = viewer_file("viewer-static");
    let html = std::fs::read_to_string(&path).unwrap();
    for external in [
        "http://",
        "https://",
        "<link",
        "@import",
        "url(",
        "src=",
        "fetch(",
        "XMLHttpRequest",
    ] {
        assert!(
            !html.contains(external),
            "viewer references something external: `{external}`"
        );
    }
    for id in [
        r#"id="view""#,
        r#"id="time-slider""#,
        r#"id="play""#,
        r#"id="field""#,
        r#"id="theta-plot""#,
    ] {
        assert!(html.contains(id), "missing element {id}");
    }
    let data = embedded_json(&html);
    assert_eq!(data["frames"].as_array().unwrap().len(), 31, "steps 0..=30");
    assert_eq!(
        data["tris"].as_array().unwrap().len(),
        triangles * 4 * 3,
        "four sub-triangles per Tri6"
    );
    let t: Vec<f64> = data["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["t"].as_f64().unwrap())
        .collect();
    assert!(t.windows(2).all(|w| w[1] > w[0]), "frames in time order");
    assert!(
        data["fields"][1]["max"].as_f64().unwrap() > 1e6,
        "von Mises scale in Pa"
    );
}

fn file_url(path: &Path) -> String {
    format!("file://{}", std::fs::canonicalize(path).unwrap().display())
}

/// The page's own check (`#selftest`) in Chromium: its JSON details and the whole DOM.
fn selftest(chrome: &Path, path: &Path) -> (serde_json::Value, String) {
    let dom = tools::run_chromium(chrome, &["--dump-dom".into(), format!("{}#selftest", file_url(path))]);
    let start =
        dom.find(r#"<pre id="selftest">"#).expect("selftest element in the DOM") + r#"<pre id="selftest">"#.len();
    let end = start + dom[start..].find("</pre>").unwrap();
    let verdict = &dom[start..end];
    assert!(
        !verdict.is_empty(),
        "the page script did not run (no verdict); DOM title: {:?}",
        dom.find("<title>")
    );
    let v: serde_json::Value = serde_json::from_str(&verdict.replace("&amp;", "&").replace("&quot;", "\""))
        .unwrap_or_else(|e| panic!("verdict is not JSON ({e}): {verdict}"));
    (v, dom)
}

/// Standard base64 (with padding), as the page's `atob` reads it.
fn base64_decode(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {:?}", c as char),
    };
    let mut out = Vec::new();
    for chunk in text.as_bytes().chunks(4) {
        let digits: Vec<u8> = chunk.iter().filter(|&&c| c != b'=').map(|&c| value(c)).collect();
        let bits = digits
            .iter()
            .enumerate()
            .fold(0u32, |a, (i, &d)| a | (d as u32) << (18 - 6 * i));
        out.extend(bits.to_be_bytes()[1..].iter().take(digits.len() - 1));
    }
    out
}

/// The values of field `k` of a frame of the embedded data, as the page decodes them (`uint16`
/// per node times `max / 65535`).
fn decoded_field(data: &serde_json::Value, frame: &serde_json::Value, k: usize) -> Vec<f64> {
    let max = data["fields"][k]["max"].as_f64().unwrap();
    base64_decode(frame["fields"][k].as_str().unwrap())
        .chunks(2)
        .map(|b| u16::from_le_bytes([b[0], b[1]]) as f64 * max / 65535.0)
        .collect()
}

/// `|u − (R(θ)X − X)|` per node of the synthetic frame at `step` (steps of `DT`): the elastic
/// displacement as `displacement.gif` defines it (the `anim` module's doc), computed here apart.
fn elastic_magnitudes(mesh: &pendulum_fem::mesh::Mesh, step: usize) -> Vec<f64> {
    let f = synthetic_frame(mesh, step, DT);
    let (s, c) = f.theta.sin_cos();
    mesh.nodes
        .iter()
        .zip(&f.displacement)
        .map(|(x, u)| {
            let rigid = [c * x[0] - s * x[1] - x[0], s * x[0] + c * x[1] - x[1]];
            (u[0] - rigid[0]).hypot(u[1] - rigid[1])
        })
        .collect()
}

/// The largest difference of `got` from `want`, which the page's 16-bit quantisation of a field of
/// largest value `max` allows to be `max / 131070` (plus the `f32` rounding of the kept values).
fn assert_quantised_equal(got: &[f64], want: &[f64], max: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: nodes");
    let worst = got.iter().zip(want).map(|(g, w)| (g - w).abs()).fold(0.0, f64::max);
    assert!(
        worst <= max / 65535.0,
        "{what}: the decoded |u| differs from the elastic |u − u_rigid| by up to {worst:e} m (scale {max:e} m)"
    );
}

#[test]
fn the_viewers_displacement_is_the_elastic_part_the_gif_draws_with_many_values_in_every_frame() {
    let (path, _) = viewer_file("viewer-elastic");
    let data = embedded_json(&std::fs::read_to_string(&path).unwrap());
    let mesh = plate_mesh(NX, NY);
    let max = data["fields"][0]["max"].as_f64().unwrap();
    let frames = data["frames"].as_array().unwrap();
    let largest = (0..frames.len())
        .flat_map(|step| elastic_magnitudes(&mesh, step))
        .fold(0.0, f64::max);
    assert!(
        (max - largest).abs() <= 1e-6 * largest,
        "the |u| scale {max:e} m is not the largest elastic displacement {largest:e} m"
    );
    for frame in frames {
        let step = frame["step"].as_u64().unwrap() as usize;
        for k in 0..2 {
            let values = decoded_field(&data, frame, k);
            let distinct: HashSet<u64> = values.iter().map(|v| v.to_bits()).collect();
            assert!(
                distinct.len() > 16,
                "step {step}, field {k}: only {} distinct values over {} nodes",
                distinct.len(),
                values.len()
            );
        }
        assert_quantised_equal(
            &decoded_field(&data, frame, 0),
            &elastic_magnitudes(&mesh, step),
            max,
            &format!("step {step}"),
        );
    }
    assert_eq!(
        data["fields"][0]["label"].as_str(),
        Some("|u − u_rigid| [m]"),
        "{}",
        data["fields"]
    );
}

#[test]
fn viewer_draws_and_the_slider_and_field_selector_change_the_picture_in_chromium() {
    let Some(chrome) = tools::chromium("viewer_draws_and_the_slider_and_field_selector_change_the_picture_in_chromium")
    else {
        return;
    };
    let (path, _) = viewer_file("viewer-selftest");
    let (v, dom) = selftest(&chrome, &path);
    assert_eq!(v["errors"].as_array().map(Vec::len), Some(0), "script errors: {v}");
    assert!(
        v["distinct_colours"].as_u64().unwrap() > 8,
        "the mesh canvas is blank: {v}"
    );
    assert_eq!(v["slider_changes_view"], true, "{v}");
    assert_eq!(v["slider_moves_marker"], true, "{v}");
    assert_eq!(v["field_changes_view"], true, "{v}");
    assert_eq!(v["slider_event_changes_view"], true, "{v}");
    assert_eq!(v["pass"], true, "{v}");
    assert!(dom.contains("<title>SELFTEST PASS</title>"));
}

#[test]
fn viewer_screenshot_in_chromium_is_not_blank() {
    let Some(chrome) = tools::chromium("viewer_screenshot_in_chromium_is_not_blank") else {
        return;
    };
    let (path, _) = viewer_file("viewer-screenshot");
    let shot = path.with_file_name("screenshot.png");
    tools::run_chromium(
        &chrome,
        &[
            "--window-size=1300,800".into(),
            format!("--screenshot={}", shot.display()),
            file_url(&path),
        ],
    );
    let dec = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(&shot).expect("screenshot written"),
    ));
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let colours: HashSet<&[u8]> = buf[..info.buffer_size()].chunks(channels).map(|p| &p[..3]).collect();
    assert!(colours.len() > 50, "screenshot has only {} colours", colours.len());
}

#[test]
fn every_viewer_field_colours_the_plate_in_many_shades_and_u_is_the_elastic_part_in_chromium() {
    let test = "every_viewer_field_colours_the_plate_in_many_shades_and_u_is_the_elastic_part_in_chromium";
    let Some(chrome) = tools::chromium(test) else {
        return;
    };
    let (path, _) = viewer_file("viewer-fields");
    let (v, _) = selftest(&chrome, &path);
    assert_eq!(v["errors"].as_array().map(Vec::len), Some(0), "script errors: {v}");
    // per field, the colour-map colours over the plate on the first and the last frame
    let colours = v["plate_colours"]
        .as_array()
        .unwrap_or_else(|| panic!("no plate_colours: {v}"));
    assert_eq!(colours.len(), 2, "{v}");
    for (k, per_frame) in colours.iter().enumerate() {
        for n in per_frame.as_array().unwrap() {
            assert!(
                n.as_u64().unwrap() > 16,
                "field {k} draws the plate in {n} colours only: {}",
                v["plate_colours"]
            );
        }
    }
    // the values the page decoded and coloured are the elastic displacement
    let data = embedded_json(&std::fs::read_to_string(&path).unwrap());
    let step = v["last_frame_step"].as_u64().unwrap() as usize;
    let got: Vec<f64> = v["last_frame_field0"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_quantised_equal(
        &got,
        &elastic_magnitudes(&plate_mesh(NX, NY), step),
        data["fields"][0]["max"].as_f64().unwrap(),
        &format!("the page's step {step}"),
    );
}
