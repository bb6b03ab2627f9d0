//! The documentation runs as written. Every ```` ```sh ````, ```` ```bash ````, ```` ```python ````
//! and ```` ```toml ```` block of `README.md`, `crates/*/README.md` and every markdown file under
//! `docs/` (the book: `docs/src/**/*.md`) is run in a fresh folder of its own, and fails this test
//! if it exits non-zero, prints nothing or takes longer than [`TIMEOUT`]:
//!
//! * shell blocks with `bash -e -o pipefail` (a failing line fails the block), Python blocks with
//!   the interpreter of `scripts/test-env` (its environment holds fmpy, syssimx, pandas, Dask and
//!   this checkout's `pendulum_fem` wheel, built and installed here);
//! * TOML blocks are configuration files: `pendulum-fem run --config block.toml` for two steps
//!   (`time.end` shortened, pictures off), so every key and value is read and checked by the
//!   program; a block that is no configuration (a sweep file) names its check instead.
//!
//! The folder looks like a checkout: links to the repository's files and folders (`crates/`,
//! `docs/`, …) and a `target/` with `target/fmu/PendulumFem.fmu` (packed here from the freshly
//! built library, as `cargo xtask fmu` packs it) and `target/release/pendulum-fem`. `PATH` starts
//! with the `pendulum-fem` built for this test and the test environment's `bin/` (`python`, `pip`,
//! `fmpy`). Everything a block writes stays in its folder (under `target/tmp/`): a file written
//! through a link into the checkout fails the test.
//!
//! A block that cannot run here says so in the markdown, in an HTML comment on the line before its
//! fence (blank lines between are allowed), and must give the reason:
//!
//! ```text
//! <!-- not run: submits a Slurm job array -->
//! <!-- check: pendulum-fem sweep --file block.toml --list -->   (TOML: run this instead)
//! ```
//!
//! A marker without its reason or command, or one the runner does not know, fails the test.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common;
use common::python as python_env;

/// The longest a block may take: the slowest blocks, the Dask sweeps (a local cluster of two
/// worker processes, eight cases), run in seconds; a block that takes minutes has a problem.
const TIMEOUT: Duration = Duration::from_secs(120);

/// The languages that are run; other fences (`text`, `rust`, a table drawn in a fence) are text.
const RUN: [&str; 4] = ["sh", "bash", "python", "toml"];

/// What the markdown says before a block.
#[derive(Debug, Clone, PartialEq)]
enum Marker {
    /// Nothing: the block runs as written.
    None,
    /// `<!-- not run: REASON -->`.
    NotRun(String),
    /// `<!-- check: COMMAND -->`: for a TOML block, the shell command that checks it (the block is
    /// the file `block.toml`).
    Check(String),
}

/// One fenced block of a markdown file.
#[derive(Debug, Clone)]
struct Block {
    /// 1-based line of the opening fence.
    line: usize,
    lang: String,
    /// The block's text with the fence's indentation removed.
    text: String,
    marker: Marker,
}

/// The fenced blocks of `markdown`, with the marker before each. An unterminated fence, a marker
/// without its reason or command, or an unknown marker is an error naming the line.
fn blocks(markdown: &str) -> Result<Vec<Block>, String> {
    let lines: Vec<&str> = markdown.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let trimmed = lines[i].trim_start();
        if !trimmed.starts_with("```") {
            i += 1;
            continue;
        }
        let indent = lines[i].len() - trimmed.len();
        let lang = trimmed.trim_start_matches('`').trim().to_string();
        let marker = marker_before(&lines, i)?;
        let start = i;
        let mut body = Vec::new();
        i += 1;
        loop {
            let Some(line) = lines.get(i) else {
                return Err(format!("line {}: the fence opened here is never closed", start + 1));
            };
            if line.trim_start().starts_with("```") {
                break;
            }
            body.push(line.get(indent..).unwrap_or(line.trim_start()));
            i += 1;
        }
        i += 1;
        if marker != Marker::None && !RUN.contains(&lang.as_str()) {
            return Err(format!(
                "line {}: a marker before a ```{lang} block, which is never run",
                start + 1
            ));
        }
        if matches!(marker, Marker::Check(_)) && lang != "toml" {
            return Err(format!(
                "line {}: `check:` is for TOML blocks; this is ```{lang}",
                start + 1
            ));
        }
        out.push(Block {
            line: start + 1,
            lang,
            text: body.join("\n") + "\n",
            marker,
        });
    }
    Ok(out)
}

/// The marker in the HTML comment on the last non-blank line before line `fence` (0-based).
fn marker_before(lines: &[&str], fence: usize) -> Result<Marker, String> {
    let Some(prev) = lines[..fence].iter().rposition(|l| !l.trim().is_empty()) else {
        return Ok(Marker::None);
    };
    let text = lines[prev].trim();
    let Some(inner) = text.strip_prefix("<!--").and_then(|t| t.strip_suffix("-->")) else {
        return Ok(Marker::None);
    };
    let inner = inner.trim();
    let at = |what: &str| format!("line {}: {what}: {text}", prev + 1);
    if let Some(reason) = inner.strip_prefix("not run") {
        let reason = reason.trim_start().strip_prefix(':').map(str::trim).unwrap_or("");
        if reason.is_empty() {
            return Err(at("`not run` needs its reason (`<!-- not run: why -->`)"));
        }
        return Ok(Marker::NotRun(reason.to_string()));
    }
    if let Some(command) = inner.strip_prefix("check:") {
        let command = command.trim();
        if command.is_empty() {
            return Err(at("`check:` needs the command that checks the block"));
        }
        return Ok(Marker::Check(command.to_string()));
    }
    Err(at(
        "an HTML comment before a fence must be `not run: REASON` or `check: COMMAND`",
    ))
}

/// The markdown files whose blocks are run: `README.md`, `crates/*/README.md` and every `.md`
/// under `docs/` (the book's chapters, `docs/src/**/*.md`).
fn documentation(root: &Path) -> Vec<PathBuf> {
    let mut files = vec![root.join("README.md")];
    let mut more = Vec::new();
    for entry in std::fs::read_dir(root.join("crates")).unwrap() {
        let readme = entry.unwrap().path().join("README.md");
        if readme.is_file() {
            more.push(readme);
        }
    }
    markdown_under(&root.join("docs"), &mut more);
    more.sort();
    files.extend(more);
    files
}

/// Every `.md` file in `dir` and its subfolders, appended to `out`.
fn markdown_under(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            markdown_under(&path, out);
        } else if path.extension().is_some_and(|e| e == "md") {
            out.push(path);
        }
    }
}

/// A fresh folder that looks like a checkout: links to the repository's entries, and `target/`
/// with the FMU and the binary where the documentation says they are.
fn checkout_like(root: &Path, dir: &Path, fmu: &Path) {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir.join("target/fmu")).unwrap();
    std::fs::create_dir_all(dir.join("target/release")).unwrap();
    for entry in std::fs::read_dir(root).unwrap() {
        let entry = entry.unwrap();
        let name = entry.file_name();
        if [".git", "target", "results"].iter().any(|n| name == *n) {
            continue;
        }
        std::os::unix::fs::symlink(entry.path(), dir.join(&name)).unwrap();
    }
    std::os::unix::fs::symlink(fmu, dir.join("target/fmu/PendulumFem.fmu")).unwrap();
    std::os::unix::fs::symlink(
        env!("CARGO_BIN_EXE_pendulum-fem"),
        dir.join("target/release/pendulum-fem"),
    )
    .unwrap();
}

/// The command that runs `block` in `dir` (the block already written there as `block.*`).
fn command(block: &Block, dir: &Path, python: &Path) -> Command {
    let mut cmd = match (block.lang.as_str(), &block.marker) {
        ("sh" | "bash", _) => {
            let mut cmd = Command::new("bash");
            cmd.args(["-e", "-o", "pipefail", "block.sh"]);
            cmd
        }
        ("python", _) => {
            let mut cmd = Command::new(python);
            cmd.arg("block.py");
            cmd
        }
        ("toml", Marker::Check(check)) => {
            let mut cmd = Command::new("bash");
            cmd.args(["-e", "-o", "pipefail", "-c", check]);
            cmd
        }
        ("toml", _) => {
            // two steps of the configured dt: every key read and range-checked, the model built and
            // stepped; results.csv only
            let mut cmd = common::bin();
            cmd.args(["run", "--config", "block.toml", "--out", "out"]);
            let dt = toml::from_str::<toml::Table>(&block.text)
                .ok()
                .and_then(|t| t.get("time")?.get("dt")?.as_float())
                .unwrap_or(0.01);
            cmd.args(["--set", &format!("time.end={}", 2.0 * dt)]);
            for key in ["plots", "animation", "paraview", "viewer"] {
                cmd.args(["--set", &format!("output.{key}=false")]);
            }
            cmd
        }
        (lang, _) => unreachable!("```{lang} is not run"),
    };
    cmd.current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    cmd
}

/// Runs `cmd` with [`TIMEOUT`]: `Ok(output)` after a zero exit with something printed, else
/// `Err(what went wrong, with all it printed)`.
fn run_block(mut cmd: Command) -> Result<String, String> {
    let started = Instant::now();
    let mut child = cmd.spawn().map_err(|e| format!("cannot start {cmd:?}: {e}"))?;
    // read both pipes on threads, so that a block printing much does not block on a full pipe
    let mut stdout = child.stdout.take().unwrap();
    let mut stderr = child.stderr.take().unwrap();
    let out = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut stdout, &mut s).ok();
        s
    });
    let err = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut stderr, &mut s).ok();
        s
    });
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break Some(status);
        }
        if started.elapsed() > TIMEOUT {
            child.kill().ok();
            child.wait().ok();
            break None;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let (stdout, stderr) = (out.join().unwrap(), err.join().unwrap());
    let printed = format!("--- stdout ---\n{stdout}--- stderr ---\n{stderr}");
    match status {
        None => Err(format!("still running after {} s\n{printed}", TIMEOUT.as_secs())),
        Some(s) if !s.success() => Err(format!("exited with {s}\n{printed}")),
        Some(_) if stdout.trim().is_empty() && stderr.trim().is_empty() => {
            Err("printed nothing: a block shows its result".to_string())
        }
        Some(_) => Ok(printed),
    }
}

/// The links of `markdown` outside fenced blocks and code spans, as `(line, target)`: the
/// targets of `[text](target)` and `![alt](target)`.
fn links(markdown: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let (mut fenced, mut code) = (false, false);
    for (n, line) in markdown.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // a code span, which may run on over the lines of its paragraph, holds no link:
        // `[a](b)` in backticks is text
        if line.trim().is_empty() {
            code = false;
        }
        let mut text = String::new();
        for c in line.chars() {
            if c == '`' {
                code = !code;
            } else if !code {
                text.push(c);
            }
        }
        let mut rest = text.as_str();
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let Some(end) = after.find(')') else { break };
            out.push((n + 1, after[..end].trim().to_string()));
            rest = &after[end + 1..];
        }
    }
    out
}

/// The anchors of the headings of `markdown`, as GitHub and mdBook make them: the heading's text
/// without its code spans' backticks and its links' targets, lower case, every character but
/// letters, digits, `_`, `-` and spaces dropped, spaces made `-`; a repeated one gets `-1`, `-2`, ….
fn anchors(markdown: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut fenced = false;
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        let Some(heading) = line.strip_prefix('#').filter(|_| !fenced) else {
            continue;
        };
        let heading = heading.trim_start_matches('#');
        if !heading.starts_with(' ') {
            continue;
        }
        // [text](target) counts as its text
        let mut text = String::new();
        let mut rest = heading.trim();
        while let Some(i) = rest.find("](") {
            text.push_str(&rest[..i]);
            rest = rest[i + 2..].split_once(')').map_or("", |(_, r)| r);
        }
        text.push_str(rest);
        let slug: String = text
            .to_lowercase()
            .chars()
            .filter(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | ' '))
            .map(|c| if c == ' ' { '-' } else { c })
            .collect();
        let repeats = out
            .iter()
            .filter(|a| {
                *a == &slug
                    || a.strip_prefix(&format!("{slug}-"))
                        .is_some_and(|n| n.parse::<u32>().is_ok())
            })
            .count();
        out.push(if repeats == 0 {
            slug
        } else {
            format!("{slug}-{repeats}")
        });
    }
    out
}

/// The broken relative links of the markdown file `file` (`text` its content): a target that is
/// no file or folder, or an anchor that is no heading of the markdown file it names.
fn broken_links(file: &Path, text: &str) -> Vec<String> {
    let mut broken = Vec::new();
    for (line, target) in links(text) {
        if target.contains("://") || target.starts_with("mailto:") {
            continue;
        }
        let (path, anchor) = match target.split_once('#') {
            Some((path, anchor)) => (path, Some(anchor)),
            None => (target.as_str(), None),
        };
        let resolved = if path.is_empty() {
            file.to_path_buf()
        } else {
            file.parent().unwrap().join(path)
        };
        if !resolved.exists() {
            broken.push(format!("line {line}: {target}: no such file"));
            continue;
        }
        let Some(anchor) = anchor else { continue };
        if resolved.extension().is_some_and(|e| e == "md") {
            let markdown = std::fs::read_to_string(&resolved).unwrap();
            if !anchors(&markdown).iter().any(|a| a == anchor) {
                broken.push(format!("line {line}: {target}: no heading #{anchor} there"));
            }
        }
    }
    broken
}

#[test]
fn every_chapter_in_the_books_summary_exists_and_every_chapter_is_in_it() {
    let src = common::root().join("docs/src");
    let summary = std::fs::read_to_string(src.join("SUMMARY.md")).unwrap();
    let listed: Vec<String> = links(&summary).into_iter().map(|(_, t)| t).collect();
    assert!(listed.len() >= 10, "SUMMARY.md lists {} chapters", listed.len());
    for chapter in &listed {
        assert!(
            !chapter.contains('#') && src.join(chapter).is_file(),
            "docs/src/SUMMARY.md lists {chapter}, which is no file of docs/src"
        );
    }
    let mut chapters = Vec::new();
    markdown_under(&src, &mut chapters);
    for chapter in chapters {
        let rel = chapter.strip_prefix(&src).unwrap().display().to_string();
        assert!(
            rel == "SUMMARY.md" || listed.contains(&rel),
            "docs/src/{rel} is not in docs/src/SUMMARY.md, so the book leaves it out"
        );
    }
}

#[test]
fn every_relative_link_of_the_documentation_reaches_a_file_and_its_heading() {
    let root = common::root();
    let mut broken = Vec::new();
    for file in documentation(root) {
        let rel = file.strip_prefix(root).unwrap().display().to_string();
        let text = std::fs::read_to_string(&file).unwrap();
        broken.extend(broken_links(&file, &text).into_iter().map(|b| format!("{rel}: {b}")));
    }
    assert!(broken.is_empty(), "broken links:\n  {}", broken.join("\n  "));
}

#[test]
fn links_and_anchors_are_read_as_github_and_mdbook_make_them() {
    let md =
        "# The `[model]` section\n\n## Full model at dt = 1 ms\n\n## A [link](x.md) in it\n\n## Again\n\n## Again\n\n\
              See [a](a.md), ![b](img/b.png) and `[not](code.md)`.\n```sh\n# no heading\necho [no](link.md)\n```\n\
              A `span\nover [two](lines.md)` and [after](c.md).\n";
    assert_eq!(
        anchors(md),
        [
            "the-model-section",
            "full-model-at-dt--1-ms",
            "a-link-in-it",
            "again",
            "again-1"
        ]
    );
    let found: Vec<String> = links(md).into_iter().map(|(_, t)| t).collect();
    assert_eq!(found, ["x.md", "a.md", "img/b.png", "c.md"]);
    let dir = common::scratch("links");
    std::fs::write(dir.join("a.md"), "# Here\n").unwrap();
    let page = dir.join("page.md");
    let text = "[ok](a.md#here) [no file](b.md) [no heading](a.md#there) [web](https://example.org/x)\n";
    let broken = broken_links(&page, text);
    assert_eq!(broken.len(), 2, "{broken:?}");
    assert!(broken[0].contains("b.md: no such file"), "{broken:?}");
    assert!(broken[1].contains("no heading #there"), "{broken:?}");
}

#[test]
fn every_documentation_block_runs_as_written_or_says_why_not() {
    let root = common::root();
    let scratch = common::scratch("blocks");
    let python = python_env::test_env_with_wheel(root);
    let fmu = python_env::pack_fmu(&scratch.join("fmu"));

    // PATH: this test's pendulum-fem, then the test environment's python, pip and fmpy
    let bin = scratch.join("bin");
    let _ = std::fs::remove_dir_all(&bin);
    std::fs::create_dir_all(&bin).unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_pendulum-fem"), bin.join("pendulum-fem")).unwrap();
    let venv_bin = python.parent().unwrap();
    let path = std::env::join_paths(
        [bin.clone(), venv_bin.to_path_buf()]
            .into_iter()
            .chain(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())),
    )
    .unwrap();

    let (mut ran, mut not_run, mut failures) = (0, Vec::new(), Vec::new());
    let started = Instant::now();
    let before = common::source_tree_files();
    for file in documentation(root) {
        let rel = file.strip_prefix(root).unwrap().display().to_string();
        let markdown = std::fs::read_to_string(&file).unwrap();
        let blocks = blocks(&markdown).unwrap_or_else(|e| panic!("{rel}: {e}"));
        for block in blocks.into_iter().filter(|b| RUN.contains(&b.lang.as_str())) {
            let at = format!("{rel}:{} (```{})", block.line, block.lang);
            if let Marker::NotRun(reason) = &block.marker {
                not_run.push(format!("{at}: {reason}"));
                continue;
            }
            let dir = scratch.join(format!("{}-{}", rel.replace(['/', '.'], "_"), block.line));
            checkout_like(root, &dir, &fmu);
            let ext = match block.lang.as_str() {
                "python" => "py",
                "toml" => "toml",
                _ => "sh",
            };
            std::fs::write(dir.join(format!("block.{ext}")), &block.text).unwrap();
            let mut cmd = command(&block, &dir, python);
            cmd.env("PATH", &path)
                .env("VIRTUAL_ENV", venv_bin.parent().unwrap())
                .env("MPLBACKEND", "Agg");
            let t = Instant::now();
            let result = run_block(cmd);
            ran += 1;
            println!(
                "{at}: {:.1} s, {}",
                t.elapsed().as_secs_f64(),
                if result.is_ok() { "ok" } else { "FAILED" }
            );
            if let Err(e) = result {
                failures.push(format!("{at} in {}:\n{}\n{e}", dir.display(), block.text));
            }
        }
    }
    println!(
        "{ran} blocks ran in {:.1} s; {} not run:\n  {}",
        started.elapsed().as_secs_f64(),
        not_run.len(),
        not_run.join("\n  ")
    );
    assert!(
        ran >= 15,
        "only {ran} blocks ran: is the documentation where this test looks?"
    );
    assert!(
        failures.is_empty(),
        "{} blocks failed:\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
    // a block's folder links to the checkout's folders: what it writes into one lands there
    common::assert_no_new_files(&before, &common::source_tree_files(), "the documentation's blocks");
}

#[test]
fn blocks_are_found_with_their_markers_and_indentation() {
    let md = "text\n\n<!-- not run: needs a cluster -->\n```sh\nsbatch job.sh\n```\n\n- item:\n\n  ```python\n  print(1)\n    x = 2\n  ```\n\n<!-- check: pendulum-fem sweep --file block.toml --list -->\n```toml\n[vary]\n```\n```text\nnot run\n```\n";
    let found = blocks(md).unwrap();
    assert_eq!(found.len(), 4);
    assert_eq!(found[0].marker, Marker::NotRun("needs a cluster".into()));
    assert_eq!((found[0].line, found[0].lang.as_str()), (4, "sh"));
    assert_eq!(
        found[1].text, "print(1)\n  x = 2\n",
        "the fence's indentation is removed"
    );
    assert_eq!(found[1].marker, Marker::None);
    assert_eq!(
        found[2].marker,
        Marker::Check("pendulum-fem sweep --file block.toml --list".into())
    );
    assert_eq!(found[3].lang, "text");
}

#[test]
fn a_marker_without_its_reason_or_an_unknown_marker_is_an_error_naming_the_line() {
    for (md, says) in [
        (
            "<!-- not run -->\n```sh\nls\n```\n",
            "line 1: `not run` needs its reason",
        ),
        (
            "<!-- not run:   -->\n```sh\nls\n```\n",
            "line 1: `not run` needs its reason",
        ),
        (
            "a\n\n<!-- skip this -->\n```sh\nls\n```\n",
            "line 3: an HTML comment before a fence",
        ),
        (
            "<!-- check: true -->\n```sh\nls\n```\n",
            "line 2: `check:` is for TOML blocks",
        ),
        (
            "<!-- not run: old -->\n```text\nls\n```\n",
            "line 2: a marker before a ```text block",
        ),
        ("```sh\nls\n", "line 1: the fence opened here is never closed"),
    ] {
        let e = blocks(md).expect_err(md);
        assert!(e.starts_with(says), "{md:?}: {e}");
    }
}

#[test]
fn a_block_that_fails_or_prints_nothing_is_a_failure_and_one_that_prints_passes() {
    let sh = |script: &str| {
        let mut cmd = Command::new("bash");
        cmd.args(["-e", "-o", "pipefail", "-c", script])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        cmd
    };
    assert!(run_block(sh("echo hello")).is_ok());
    let e = run_block(sh("true")).unwrap_err();
    assert!(e.contains("printed nothing"), "{e}");
    let e = run_block(sh("echo first; false; echo never")).unwrap_err();
    assert!(
        e.contains("exited with") && e.contains("first") && !e.contains("never"),
        "{e}"
    );
}
