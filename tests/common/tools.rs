//! External tools some tests need (meshio, Chromium, Gmsh), used as
//! `#[path = "common/tools.rs"] mod tools;`.
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
pub fn on_path(names: &[&str]) -> Option<std::path::PathBuf> {
    let paths = std::env::var_os("PATH")?;
    names.iter().find_map(|name| {
        std::env::split_paths(&paths)
            .map(|d| d.join(name))
            .find(|p| p.is_file())
    })
}
