//! External tools some tests need (meshio, Chromium, Gmsh), in `common::tools`.
//!
//! [`tool_or_skip`]: with `CI` set, a missing tool fails the test with what to install; elsewhere
//! the test returns early after a warning line written straight to the process's stderr, which the
//! test harness does not capture, so it shows without `--nocapture`:
//!
//! ```text
//! warning: SKIPPED meshio_reads_every_frame_back_with_equal_values: python3 with meshio not found (pip install meshio)
//! ```
#![allow(dead_code)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Whether the test may use the tool. `available`: the probe's result; `what`: the tool as a user
/// would name it; `install`: how to get it.
///
/// # Panics
/// When the tool is missing and the `CI` environment variable is set.
#[track_caller]
pub fn tool_or_skip(test: &str, available: bool, what: &str, install: &str) -> bool {
    if available {
        return true;
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "{test}: {what} not found, and CI is set: the CI machine must have it ({install}; .ci/run installs it)"
    );
    // Not eprintln!: the harness captures the print macros, not direct writes to the stream.
    let _ = writeln!(
        std::io::stderr(),
        "warning: SKIPPED {test}: {what} not found ({install})"
    );
    false
}

/// Whether `python3 -c "import <module>"` succeeds.
pub fn python_module(module: &str) -> bool {
    std::process::Command::new("python3")
        .args(["-c", &format!("import {module}")])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// The first of `names` found on `PATH`.
pub fn on_path(names: &[&str]) -> Option<PathBuf> {
    let paths = std::env::var_os("PATH")?;
    names.iter().find_map(|name| {
        std::env::split_paths(&paths)
            .map(|d| d.join(name))
            .find(|p| p.is_file())
    })
}

/// The Chromium binary for `test`; `None` (after the warning of [`tool_or_skip`]) when it is
/// missing outside CI, a failure on CI.
#[track_caller]
pub fn chromium(test: &str) -> Option<PathBuf> {
    let found = on_path(&["chromium", "chromium-browser", "google-chrome"]);
    tool_or_skip(test, found.is_some(), "chromium", "apt-get install chromium").then_some(found?)
}

/// Runs headless Chromium with `args` and a fresh profile; returns stdout. Fails after 90 s.
pub fn run_chromium(binary: &Path, args: &[String]) -> String {
    let profile = super::scratch("chromium-profile");
    let mut child = Command::new(binary)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start chromium");
    let mut stdout = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut stdout, &mut s).unwrap();
        s
    });
    let deadline = Instant::now() + Duration::from_secs(90);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium did not finish within 90 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let _ = std::fs::remove_dir_all(&profile);
    reader.join().unwrap()
}
