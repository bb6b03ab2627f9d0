//! The HTML viewer: one self-contained file that draws and responds to its controls, checked in
//! headless Chromium (`.ci/run` installs it; elsewhere the browser tests skip with a visible
//! warning, and fail when `CI` is set).

use crate::common;
use common::{plate, tools};

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use pendulum_fem::config::Output;
use plate::*;

/// Writes a viewer for a 30-step swing and returns its path.
fn viewer_file(name: &str) -> (PathBuf, usize) {
    let dir = common::scratch(name);
    let mesh = plate_mesh(2, 10);
    let output = Output {
        plots: false,
        animation: false,
        paraview: false,
        ..all_outputs()
    };
    run(&dir, &mesh, &output, 30, 0.01);
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

#[test]
fn viewer_draws_and_the_slider_and_field_selector_change_the_picture_in_chromium() {
    let Some(chrome) = tools::chromium("viewer_draws_and_the_slider_and_field_selector_change_the_picture_in_chromium")
    else {
        return;
    };
    let (path, _) = viewer_file("viewer-selftest");
    let dom = tools::run_chromium(&chrome, &["--dump-dom".into(), format!("{}#selftest", file_url(&path))]);
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
