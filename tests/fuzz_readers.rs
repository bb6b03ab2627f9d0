//! Bounded property-based fuzzing of the readers of user files: configuration TOML (and `--set`
//! overrides), torque tables (CSV), Gmsh meshes (ASCII and binary) and snapshots (checkpoints). Each reader, fed mutated
//! valid files or arbitrary input, returns a value or an error that names its source, and never
//! panics. These run 300 cases each in seconds with the suite; a long campaign sets the number of
//! cases per test with the environment variable `FUZZ_CASES`, e.g.
//! `FUZZ_CASES=2000000 cargo test --release --test suite fuzz_readers::` (see docs/src/development.md).

use crate::common;
use common::msh;

use std::sync::OnceLock;

use pendulum_fem::config::{commented_default, Config};
use pendulum_fem::mesh::gmsh_read::parse_msh;
use pendulum_fem::render::gmsh::write_msh_to;
use pendulum_fem::simulation::{Simulation, Snapshot};
use pendulum_fem::store::fnv1a;
use pendulum_fem::terms::TorqueTable;
use proptest::prelude::*;

/// A small valid mesh file (the plate of 2 × 6 squares), ASCII and binary.
fn valid_msh() -> &'static (Vec<u8>, Vec<u8>) {
    static FILES: OnceLock<(Vec<u8>, Vec<u8>)> = OnceLock::new();
    FILES.get_or_init(|| {
        let mut cfg = Config::default();
        cfg.mesh.refine = 0.25; // a coarse pendulum keeps each case fast
        let mesh = pendulum_fem::mesh::generate(&cfg).unwrap();
        let mut ascii = Vec::new();
        write_msh_to(&mut ascii, &mesh).unwrap();
        (ascii, msh::binary_msh(&mesh))
    })
}

/// A coarse pendulum's configuration and a snapshot of it after three steps (with a torque, so
/// that every optional part of the format is present).
fn valid_snapshot() -> &'static (Config, Vec<u8>) {
    static SNAP: OnceLock<(Config, Vec<u8>)> = OnceLock::new();
    SNAP.get_or_init(|| {
        let mut cfg = Config::default();
        cfg.mesh.refine = 0.25;
        cfg.torque.profile = pendulum_fem::config::TorqueProfile::Constant;
        cfg.torque.amplitude = 0.1;
        let mut sim = Simulation::from_config(&cfg, pendulum_fem::mesh::generate(&cfg).unwrap()).unwrap();
        for _ in 0..3 {
            sim.step(cfg.time.dt).unwrap();
        }
        (cfg, sim.snapshot().to_bytes())
    })
}

/// Reads `data` as a snapshot and, when it reads, restores it into a fresh simulation of the model
/// it was made for: each step either works or is an error (never a panic); read errors name the file.
fn assert_snapshot(data: &[u8]) {
    match Snapshot::from_bytes(data, "fuzz.snap") {
        Err(e) => assert!(
            e.to_string().contains("fuzz.snap"),
            "an error that does not name the file: {e}"
        ),
        Ok(snapshot) => {
            let cfg = &valid_snapshot().0;
            let mut sim = Simulation::from_config(cfg, pendulum_fem::mesh::generate(cfg).unwrap()).unwrap();
            if let Err(e) = sim.restore(&snapshot) {
                assert!(!e.to_string().is_empty());
            }
        }
    }
}

/// An edit of a byte string: overwrite, insert or delete a short run at a position (as fractions).
#[derive(Clone, Debug)]
enum Edit {
    Overwrite(f64, Vec<u8>),
    Insert(f64, Vec<u8>),
    Delete(f64, usize),
    Truncate(f64),
}

fn edit() -> impl Strategy<Value = Edit> {
    let bytes = prop::collection::vec(any::<u8>(), 1..8);
    let text = "[-0-9eE.+ \n$\"a-z]{1,8}".prop_map(String::into_bytes);
    prop_oneof![
        (0.0..1.0f64, bytes.clone()).prop_map(|(p, b)| Edit::Overwrite(p, b)),
        (0.0..1.0f64, text.clone()).prop_map(|(p, b)| Edit::Overwrite(p, b)),
        (0.0..1.0f64, text).prop_map(|(p, b)| Edit::Insert(p, b)),
        (0.0..1.0f64, bytes).prop_map(|(p, b)| Edit::Insert(p, b)),
        (0.0..1.0f64, 1..64usize).prop_map(|(p, n)| Edit::Delete(p, n)),
        (0.0..1.0f64).prop_map(Edit::Truncate),
    ]
}

fn apply(data: &[u8], edits: &[Edit]) -> Vec<u8> {
    let mut d = data.to_vec();
    for e in edits {
        let at = |p: f64, d: &Vec<u8>| ((p * d.len() as f64) as usize).min(d.len());
        match e {
            Edit::Overwrite(p, b) => {
                let i = at(*p, &d);
                for (k, &x) in b.iter().enumerate() {
                    if let Some(slot) = d.get_mut(i + k) {
                        *slot = x;
                    }
                }
            }
            Edit::Insert(p, b) => {
                let i = at(*p, &d);
                d.splice(i..i, b.iter().copied());
            }
            Edit::Delete(p, n) => {
                let i = at(*p, &d);
                let j = (i + n).min(d.len());
                d.drain(i..j);
            }
            Edit::Truncate(p) => {
                let i = at(*p, &d);
                d.truncate(i);
            }
        }
    }
    d
}

/// Cases per property: `FUZZ_CASES` when set (a long campaign), 300 otherwise.
fn fuzz_cases() -> u32 {
    std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(300)
}

/// Every key a `--set` can name: the leaves of the default configuration (optional keys that are
/// unset by default, `mesh.file`, `torque.file` and `initial.elastic`, added).
fn config_keys() -> &'static [String] {
    static KEYS: OnceLock<Vec<String>> = OnceLock::new();
    KEYS.get_or_init(|| {
        fn walk(prefix: &str, v: &toml::Value, out: &mut Vec<String>) {
            match v {
                toml::Value::Table(t) => {
                    for (k, v) in t {
                        let key = if prefix.is_empty() {
                            k.clone()
                        } else {
                            format!("{prefix}.{k}")
                        };
                        walk(&key, v, out);
                    }
                }
                _ => out.push(prefix.to_string()),
            }
        }
        let mut keys = Vec::new();
        walk("", &toml::Value::try_from(Config::default()).unwrap(), &mut keys);
        for optional in ["mesh.file", "torque.file", "initial.elastic"] {
            if !keys.iter().any(|k| k == optional) {
                keys.push(optional.to_string());
            }
        }
        keys
    })
}

/// The words the commented default configuration quotes (the choices of its enumerations).
fn config_words() -> &'static [String] {
    static WORDS: OnceLock<Vec<String>> = OnceLock::new();
    WORDS.get_or_init(|| {
        let text = commented_default();
        let mut words: Vec<String> = text
            .split('"')
            .skip(1)
            .step_by(2)
            .filter(|w| !w.is_empty() && w.len() <= 24 && !w.contains(' '))
            .map(String::from)
            .collect();
        words.sort();
        words.dedup();
        words
    })
}

/// The key of a `--set`: one of the configuration's keys, or a made-up one.
fn set_key() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => prop::sample::select(config_keys().to_vec()),
        1 => "(geometry|mesh|material|gravity|initial|time|solver|torque|output|x)\\.[a-z_]{1,20}",
    ]
}

/// The value of a `--set`: numbers, booleans, the configuration's words (bare and quoted), and
/// arbitrary text.
fn set_value() -> impl Strategy<Value = String> {
    prop_oneof![
        (-1e3..1e3f64).prop_map(|v| format!("{v}")),
        (0.0..1.0f64).prop_map(|v| format!("{v:e}")),
        (0..100i64).prop_map(|v| v.to_string()),
        any::<bool>().prop_map(|b| b.to_string()),
        prop::sample::select(config_words().to_vec()),
        prop::sample::select(config_words().to_vec()).prop_map(|w| format!("\"{w}\"")),
        "[-0-9eE.+a-z\"\\[\\] ]{0,12}",
    ]
}

/// The value at the dotted `key` of a TOML document.
fn leaf<'a>(doc: &'a toml::Value, key: &str) -> Option<&'a toml::Value> {
    key.split('.').try_fold(doc, |v, part| v.get(part))
}

/// A `--set` value as the command line documents it: TOML when it reads as a TOML value, the
/// text itself (a bare word) otherwise. Written here from that rule, not taken from the program.
fn typed(value: &str) -> toml::Value {
    match format!("v = {}", value.trim()).parse::<toml::Table>() {
        Ok(mut t) => t.remove("v").unwrap(),
        Err(_) => toml::Value::String(value.trim().to_string()),
    }
}

/// Whether the configuration's `held` value is the `given` one: numbers by value (an integer
/// given for a real key is that real), NaN as NaN, arrays element by element.
fn same_value(held: &toml::Value, given: &toml::Value) -> bool {
    use toml::Value::{Array, Float, Integer};
    let number = |v: &toml::Value| match v {
        Integer(i) => Some(*i as f64),
        Float(x) => Some(*x),
        _ => None,
    };
    match (held, given) {
        (Array(a), Array(b)) => a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same_value(x, y)),
        _ => match (number(held), number(given)) {
            (Some(x), Some(y)) => x == y || (x.is_nan() && y.is_nan()),
            _ => held == given,
        },
    }
}

fn assert_msh(data: &[u8]) {
    if let Err(e) = parse_msh(data, "fuzz.msh") {
        let m = e.to_string();
        assert!(m.contains("fuzz.msh"), "an error that does not name the file: {m}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: fuzz_cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn a_mutated_ascii_gmsh_file_is_read_or_rejected_with_an_error_naming_it(edits in prop::collection::vec(edit(), 1..4)) {
        assert_msh(&apply(&valid_msh().0, &edits));
    }

    #[test]
    fn a_mutated_binary_gmsh_file_is_read_or_rejected_with_an_error_naming_it(edits in prop::collection::vec(edit(), 1..4)) {
        assert_msh(&apply(&valid_msh().1, &edits));
    }

    #[test]
    fn arbitrary_bytes_are_no_gmsh_file(data in prop::collection::vec(any::<u8>(), 0..400)) {
        let mut with_header = b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n".to_vec();
        with_header.extend(&data);
        assert_msh(&data);
        assert_msh(&with_header);
    }

    #[test]
    fn a_mutated_snapshot_is_read_or_rejected_with_an_error_naming_it(edits in prop::collection::vec(edit(), 1..4)) {
        assert_snapshot(&apply(&valid_snapshot().1, &edits));
    }

    #[test]
    fn a_mutated_snapshot_with_a_valid_checksum_is_read_or_rejected_without_a_panic(
        edits in prop::collection::vec(edit(), 1..4),
    ) {
        // mutate the body, then append the checksum of what is left (past the magic and version
        // when they survive, into the field parser)
        let data = &valid_snapshot().1;
        let mut body = apply(&data[..data.len() - 8], &edits);
        let sum = fnv1a(&body);
        body.extend_from_slice(&sum.to_le_bytes());
        assert_snapshot(&body);
    }

    #[test]
    fn arbitrary_bytes_are_no_snapshot(data in prop::collection::vec(any::<u8>(), 0..200)) {
        let mut with_header = b"PFEMSNAP\x01\x00\x00\x00".to_vec();
        with_header.extend(&data);
        let sum = fnv1a(&with_header);
        with_header.extend_from_slice(&sum.to_le_bytes());
        assert_snapshot(&data);
        assert_snapshot(&with_header);
    }

    #[test]
    fn a_mutated_configuration_is_read_or_rejected_with_an_error(edits in prop::collection::vec(edit(), 1..4)) {
        let text = String::from_utf8_lossy(&apply(commented_default().as_bytes(), &edits)).into_owned();
        if let Err(e) = Config::from_toml_str(&text) {
            prop_assert!(!e.to_string().is_empty());
        }
    }

    #[test]
    fn any_set_override_is_applied_or_rejected_with_an_error(key in set_key(), value in set_value()) {
        let assignment = format!("{key}={value}");
        match Config::load(None, std::slice::from_ref(&assignment)) {
            Err(e) => prop_assert!(!e.to_string().is_empty()),
            Ok(cfg) => {
                // accepted: the configuration holds the value at the key
                let doc = toml::Value::try_from(&cfg).unwrap();
                let held = leaf(&doc, &key);
                prop_assert!(held.is_some(), "--set {}: accepted, but the configuration has no key {}", assignment, key);
                let given = typed(&value);
                prop_assert!(
                    same_value(held.unwrap(), &given),
                    "--set {}: accepted, but the configuration holds {:?}, not {:?}",
                    assignment,
                    held.unwrap(),
                    given
                );
            }
        }
    }

    #[test]
    fn a_torque_table_is_read_or_rejected_with_an_error_naming_the_file(
        rows in prop::collection::vec(("[-0-9eE.+ a-z]{0,8}", "[-0-9eE.+ a-z]{0,8}"), 0..12),
        header in prop_oneof![Just("time_s,torque_Nm".to_string()), "[a-z_,]{0,20}"],
    ) {
        let mut text = header.clone();
        for (t, m) in &rows {
            text.push_str(&format!("\n{t},{m}"));
        }
        match TorqueTable::parse(&text, "fuzz.csv") {
            Ok(p) => {
                // a table that reads evaluates to finite torques everywhere
                for t in [-1.0, 0.0, 0.5, 1e3] {
                    prop_assert!(p.value(t).is_finite());
                }
            }
            Err(e) => prop_assert!(e.to_string().contains("fuzz.csv"), "{}", e),
        }
    }
}
