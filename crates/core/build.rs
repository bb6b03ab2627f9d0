//! Hashes the crate's sources into `PENDULUM_FEM_SOURCE_HASH` (FNV-1a over every file under
//! `src/`, in sorted path order, names and contents), so that anything this build computes and
//! caches on disk (the reduced body's set-up, `reduced::cache`) is keyed by the code that
//! computed it: a changed source is a new key, never a stale result.

use std::path::{Path, PathBuf};

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            files(&p, out);
        } else {
            out.push(p);
        }
    }
}

fn main() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    println!("cargo:rerun-if-changed=src");
    let mut all = Vec::new();
    files(&src, &mut all);
    all.sort();
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for b in bytes {
            h ^= u64::from(*b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for p in &all {
        eat(p.strip_prefix(&src).unwrap_or(p).to_string_lossy().as_bytes());
        eat(&std::fs::read(p).unwrap_or_default());
    }
    println!("cargo:rustc-env=PENDULUM_FEM_SOURCE_HASH={h:016x}");
}
