//! A seeded random-case campaign across what a user may set, each case run through the CLI's run
//! driver ([`pendulum_fem::commands::run::run`], with its energy watchdog at the default 0.01) on
//! the default solver settings.
//!
//! **What is drawn** (uniform unless said otherwise; `log` = uniform in the logarithm):
//! - material: Neo-Hookean, `E` log 3e5…2.1e11 Pa; Saint Venant–Kirchhoff for half of the cases
//!   with `E ≥ 1e9` Pa only. SVK's stored energy loses convexity in compression (its stiffness
//!   vanishes at a principal stretch of 1/√3 and the energy falls for harder compression), so a
//!   soft SVK plate striking a wall can collapse for the material's reasons, not the solver's; at
//!   `E ≥ 1e9` Pa the strains of these loads stay below 1e-3, where SVK is an admissible law.
//!   `ν` 0.2…0.45, density 900…8000 kg/m³;
//! - geometry within the keys' ranges around the tutorial: rod half-width 8…25 mm, head radius
//!   (rod + 15 mm)…(rod + 60 mm), a hole in two cases of three (0.3…0.7 of the head radius),
//!   pivot to head centre 1.3…3 head radii (+ the rod), thickness 5…20 mm; `mesh.refine` 1…2;
//! - `θ₀` −170°…170° (0°…170° with a wall: the wall lies to the left of the hanging head, and a
//!   pendulum released on its far side is a configuration error, see `check_wall_clearance`),
//!   `ω₀` −8…8 rad/s, gravity on (g = 9.81) or off in one case of five;
//! - `time.dt` log 1…20 ms, `time.end` 1…2 s;
//! - torque: none, constant, step or sine (0.2…20 Hz), amplitude −1…1 N·m;
//! - wall: none, rigid or deformable (one third each), the face 0…40 mm left of the hanging
//!   head, the block's `E` log 1e7…2.1e11 Pa; contact stiffness log 1e9…1e13 N/m³.
//!
//! **What must hold** for every case: the run finishes; no NaN in `results.csv`; the energy
//! balance (the total-energy change minus the torque's work) within 1e-6 of the run's available
//! energy (the run summary's energy error, [`pendulum_fem::commands::run::EnergyAudit`]: initial
//! kinetic energy + weight × the centroid's possible height change + the torque's largest |work|,
//! at least 1e-3 m g₀ L); and with a wall, the largest penetration within twice the penetration
//! `δ_E` at which the contact energy of the head's arc (a cylinder of radius R on a plane,
//! `k t (8/15) √(2R) δ^{5/2}`) equals the available energy: energy conservation allows no more,
//! and the factor 2 covers the arc's Gauss-point quadrature and a head flattened by a soft
//! material (which lowers the penetration, never raises the energy). A case outside the model
//! must stop with the error naming that cause (see [`accepted_error`]).
//!
//! `ROBUST_CASES=N` runs N cases (default [`CI_CASES`]), `ROBUST_SEED=S` another seed,
//! `ROBUST_FIRST=K` starts at case K, and `ROBUST_ONLY=5,12,13` runs just those cases of the seed
//! (as a campaign: every case asserted). Each failing case is printed as a configuration file that
//! `pendulum-fem run --config FILE` runs. The campaign prints the distribution of Newton
//! iterations per step and of cut-backs per case.
//!
//! `ROBUST_MACHINE=alone` gives each case [`ALONE_SECONDS`] (the machine runs nothing but the
//! campaign), `shared` [`CASE_SECONDS`] (other work beside it), which is also the limit without
//! it. `ROBUST_LEDGER=1` (with `ROBUST_CASES`, `ROBUST_SEED` and `ROBUST_MACHINE`) records the
//! campaign in the ledger `tests/campaign/ledger.csv` ([`ledger`]; `scripts/campaign` runs one):
//! a seed never run before, refused otherwise.

use crate::common;
#[path = "robustness/ledger.rs"]
mod ledger;
use common::Extremes;

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use pendulum_fem::commands::run::{run, RunEnd, RunOptions, RunSummary};
use pendulum_fem::render::plot::History;
use pendulum_fem::run::rows::{read_events, read_records};
use pendulum_fem::store::Table;
use pendulum_fem::Config;

/// Cases run by `cargo test` (without `ROBUST_CASES`).
const CI_CASES: usize = 12;

/// Wall time after which a case counts as hanging \[s\]: far above what a passing case of the CI
/// range needs beside a second case; a campaign's limit on a machine shared with other work
/// (`ROBUST_MACHINE=shared`).
const CASE_SECONDS: u64 = 120;

/// The wall time a case of a campaign that has the machine to itself may take \[s\]
/// (`ROBUST_MACHINE=alone`).
const ALONE_SECONDS: u64 = 60;

/// The version of [`draw`]'s draws, named in a ledger row: a new one whenever what a seed draws
/// changes.
const DRAWS: &str = "v1";

/// Seeds whose cases the program was worked on against (the CI range's seed and those of earlier
/// campaigns): no blind sample, so no ledger campaign draws them.
const WORKED_SEEDS: &[u64] = &[17, 18, 20, 24, 25];

/// The wall time a known open case ([`KNOWN_OPEN`]) gets in the CI range \[s\]: enough to show
/// whether it fails without spending CI's time on an outcome that is not asserted; one that
/// passes in it is reported, to be taken off the list. A long campaign gives every case
/// [`CASE_SECONDS`].
const KNOWN_OPEN_SECONDS: u64 = 15;

/// The energy balance's bar, over the available energy.
const ENERGY_BAR: f64 = 1e-6;

/// SplitMix64: a small, seeded, reproducible generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// Rounds to 4 significant digits, so the printed configuration is the case itself.
fn sig(x: f64) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    let digits = 3 - x.abs().log10().floor() as i32;
    let f = 10f64.powi(digits);
    (x * f).round() / f
}

/// One drawn case: its number and the TOML text of its configuration.
struct Case {
    index: usize,
    toml: String,
    /// `none`, `rigid` or `deformable`.
    wall: &'static str,
    /// The head radius and thickness \[m\] and contact stiffness \[N/m³\] (with a wall).
    contact: Option<(f64, f64, f64)>,
}

fn draw(seed: u64, index: usize) -> Case {
    let mut r = Rng(seed ^ (index as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
    let mut sections: Vec<(&str, Vec<String>)> = Vec::new();
    let mut section = |name: &'static str, lines: Vec<String>| sections.push((name, lines));
    // geometry
    let rod = sig(r.uniform(0.008, 0.025));
    let head = sig(rod + r.uniform(0.015, 0.06));
    let hole = if r.below(3) > 0 {
        sig(r.uniform(0.3, 0.7) * head)
    } else {
        0.0
    };
    let distance = sig(r.uniform(1.3, 3.0) * head + rod);
    let thickness = sig(r.uniform(0.005, 0.02));
    section(
        "geometry",
        vec![
            format!("rod_half_width = {rod}"),
            format!("head_radius = {head}"),
            format!("hole_radius = {hole}"),
            format!("head_center_distance = {distance}"),
            format!("thickness = {thickness}"),
        ],
    );
    section("mesh", vec![format!("refine = {}", sig(r.uniform(1.0, 2.0)))]);
    // material
    let e = sig(r.log_uniform(3e5, 2.1e11));
    let svk = e >= 1e9 && r.below(2) == 0;
    section(
        "material",
        vec![
            format!(
                "model = \"{}\"",
                if svk { "saint-venant-kirchhoff" } else { "neo-hookean" }
            ),
            format!("youngs_modulus = {e:e}"),
            format!("poisson_ratio = {}", sig(r.uniform(0.2, 0.45))),
            format!("density = {}", sig(r.uniform(900.0, 8000.0))),
        ],
    );
    let gravity = if r.below(5) == 0 { 0.0 } else { 9.81 };
    section("gravity", vec![format!("g = {gravity}")]);
    let wall = ["none", "rigid", "deformable"][r.below(3) as usize];
    let angle = if wall == "none" {
        sig(r.uniform(-170.0, 170.0))
    } else {
        sig(r.uniform(0.0, 170.0))
    };
    section(
        "initial",
        vec![
            format!("angle_deg = {angle}"),
            format!("angular_velocity = {}", sig(r.uniform(-8.0, 8.0))),
        ],
    );
    section(
        "time",
        vec![
            format!("dt = {:e}", sig(r.log_uniform(1e-3, 2e-2))),
            format!("end = {}", sig(r.uniform(1.0, 2.0))),
        ],
    );
    let profile = ["none", "constant", "step", "sine"][r.below(4) as usize];
    let amplitude = sig(r.uniform(-1.0, 1.0));
    let mut torque = vec![format!("profile = \"{profile}\"")];
    match profile {
        "none" => {}
        "step" => torque.extend([
            format!("amplitude = {amplitude}"),
            format!("start = {}", sig(r.uniform(0.0, 1.0))),
        ]),
        "sine" => torque.extend([
            format!("amplitude = {amplitude}"),
            format!("frequency = {}", sig(r.log_uniform(0.2, 20.0))),
        ]),
        _ => torque.push(format!("amplitude = {amplitude}")),
    }
    section("torque", torque);
    let mut contact = None;
    if wall != "none" {
        let x = sig(-head - r.uniform(0.0, 0.04));
        let mut lines = vec![format!("kind = \"{wall}\""), format!("x = {x}")];
        if wall == "deformable" {
            lines.push(format!("youngs_modulus = {:e}", sig(r.log_uniform(1e7, 2.1e11))));
            lines.push(format!("center_y = {}", sig(-distance)));
        }
        section("wall", lines);
        let k = sig(r.log_uniform(1e9, 1e13));
        section("contact", vec![format!("stiffness = {k:e}")]);
        contact = Some((head, thickness, k));
    }
    section(
        "output",
        vec![
            "plots = false".into(),
            "animation = false".into(),
            "paraview = false".into(),
            "viewer = false".into(),
        ],
    );
    let mut toml = format!("# robustness case {index} (seed {seed})\n");
    for (name, lines) in sections {
        toml.push_str(&format!("\n[{name}]\n"));
        for l in lines {
            toml.push_str(&l);
            toml.push('\n');
        }
    }
    Case {
        index,
        toml,
        wall,
        contact,
    }
}

/// Cases of seed 17 in the CI range that do not pass reliably within [`CASE_SECONDS`] beside a
/// second case (issue 17 is open on them), with what each case is. In the CI range they run for
/// [`KNOWN_OPEN_SECONDS`] and their outcome is printed with their configuration, but not
/// asserted, so that the campaign guards every other case; a long campaign (`ROBUST_CASES=N`, any
/// seed) asserts every case. All but one strike a wall: inside an impact, while contact points
/// change state, Newton's iterations contract slowly, and a stiff contact's sub-steps are short;
/// the other is a light plate spun so fast that its quarter-turn sub-steps are many.
const KNOWN_OPEN: &[(usize, &str)] = &[
    (
        0,
        "SVK E = 2e9 Pa against a 33 MPa deformable block, dt 1.1 ms, 16 impacts",
    ),
    (
        2,
        "SVK E = 5e10 Pa, rigid wall k = 4.4e12 N/m³, dt 11 ms, spun to 90 rad/s",
    ),
    (3, "SVK E = 2e10 Pa, rigid wall k = 1.7e12 N/m³, dt 10 ms"),
    (7, "NH E = 2e7 Pa, rigid wall k = 1.2e12 N/m³, dt 16 ms"),
    (
        9,
        "NH E = 1.2e8 Pa, rigid wall k = 1.5e11 N/m³, dt 2.8 ms, 9638 unknowns",
    ),
    (
        10,
        "no wall; a torque spins a 70 g plate to ~1800 rad/s at dt 13 ms: quarter-turn sub-steps",
    ),
];

/// Errors that name a cause outside the model, which a case may end with: a torque whose
/// traction on the hinge edge strains a soft hub past a fifth of its modulus
/// (`Torque::check_hub_stress`; soft Neo-Hookean plates driven by up to 1 N·m through a rod
/// 8 mm wide and 5 mm thick), and a head that swings over the pivot and comes round the
/// deformable wall's face onto the block (`WallContact::behind_face` on a failed step,
/// `WallContact::came_round` on a step taken: the face is its only contact surface). Every other
/// case must finish.
fn accepted_error(message: &str) -> bool {
    message.contains("outside the model")
        && (message.contains("drives the hinge edge with a traction stress")
            || message.contains("come round the face's end"))
}

/// Why a case failed: the outcome recorded in the ledger's runs file and the description printed.
struct Failed {
    outcome: ledger::Outcome,
    why: String,
}

impl Failed {
    fn new(outcome: ledger::Outcome, why: String) -> Failed {
        Failed { outcome, why }
    }
}

impl From<String> for Failed {
    fn from(why: String) -> Failed {
        Failed::new(ledger::Outcome::Error, why)
    }
}

impl From<&str> for Failed {
    fn from(why: &str) -> Failed {
        why.to_string().into()
    }
}

/// What one case measured.
#[derive(Default)]
struct Measured {
    /// The accepted error of a case outside the model ([`accepted_error`]).
    outside: Option<String>,
    /// Newton iterations of every output step.
    iterations: Vec<usize>,
    cutbacks: usize,
    steps: usize,
    seconds: f64,
}

/// Runs `case`, stopping it after `limit` seconds of wall time; `Err` with what failed.
fn run_case(case: &Case, root: &std::path::Path, limit: u64) -> Result<Measured, Failed> {
    let config = Config::from_toml_str(&case.toml).map_err(|e| format!("configuration refused: {e}"))?;
    let out = root.join(format!("case-{}", case.index));
    let stop = Arc::new(AtomicBool::new(false));
    let opts = RunOptions {
        config,
        out: Some(out.clone()),
        force: true,
        observers: vec![pendulum_fem::render::pictures::attach()],
        stop: Some(stop.clone()),
        ..Default::default()
    };
    let started = std::time::Instant::now();
    // a case that has not finished in `limit` seconds is stopped at its next step (and fails)
    let (done, finished) = std::sync::mpsc::channel::<()>();
    let result = std::thread::scope(|s| {
        s.spawn(move || {
            if finished.recv_timeout(std::time::Duration::from_secs(limit)).is_err() {
                stop.store(true, Ordering::SeqCst);
            }
        });
        let result = run(&opts);
        let _ = done.send(());
        result
    });
    let summary: RunSummary = match result {
        Ok(s) if s.end == RunEnd::Interrupted => {
            return Err(Failed::new(
                ledger::Outcome::Late,
                format!(
                    "not finished after {limit} s of wall time (stopped at t = {} s, {} steps, {} cut-backs)",
                    s.time_reached, s.steps, s.cutbacks
                ),
            ))
        }
        Ok(s) => s,
        Err(e) if accepted_error(&e.to_string()) => {
            return Ok(Measured {
                outside: Some(e.to_string()),
                ..Default::default()
            })
        }
        Err(e) => return Err(format!("the run failed: {e}").into()),
    };
    let seconds = started.elapsed().as_secs_f64();
    // the stop is seen between steps: a run whose last step ends past the limit finishes, but late
    if seconds > limit as f64 {
        return Err(Failed::new(
            ledger::Outcome::Late,
            format!(
                "finished only after {seconds:.1} s of wall time (limit {limit} s; {} steps, {} cut-backs)",
                summary.steps, summary.cutbacks
            ),
        ));
    }
    let (names, rows) = Table::read(&out.join("results.csv"))
        .map(|t| (t.names, t.rows))
        .map_err(|e| e.to_string())?;
    if let Some((i, _)) = rows.iter().enumerate().find(|(_, r)| r.iter().any(|x| x.is_nan())) {
        return Err(Failed::new(ledger::Outcome::Nan, format!("NaN in results.csv row {i}")));
    }
    if summary.energy_error > ENERGY_BAR || !summary.energy_error.is_finite() {
        return Err(Failed::new(
            ledger::Outcome::Energy,
            format!(
                "energy balance {:.3e} of the available energy {:.4e} J (bar {ENERGY_BAR})",
                summary.energy_error, summary.energy_scale
            ),
        ));
    }
    if let Some((radius, thickness, k)) = case.contact {
        let bound = 2.0 * (summary.energy_scale / (k * thickness * (8.0 / 15.0) * (2.0 * radius).sqrt())).powf(0.4);
        let gap = names.iter().position(|c| c == "gap_m").ok_or("no gap_m column")?;
        let mut deepest = rows.iter().map(|r| -r[gap]).max_of();
        let events = out.join("events.csv");
        if events.is_file() {
            // the largest penetration of every impact (the event column is text)
            let text = std::fs::read_to_string(&events).map_err(|e| e.to_string())?;
            let mut lines = text.lines();
            let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
            let p = header
                .iter()
                .position(|c| *c == "max_penetration_m")
                .ok_or("no max_penetration_m")?;
            for line in lines {
                let cell = line.split(',').nth(p).ok_or("short events.csv row")?;
                let penetration = cell.parse::<f64>().map_err(|e| format!("events.csv {cell}: {e}"))?;
                deepest = [deepest, penetration].into_iter().max_of();
            }
        }
        if deepest > bound {
            return Err(Failed::new(
                ledger::Outcome::Penetration,
                format!("largest penetration {deepest:.3e} m above the bound {bound:.3e} m of the contact stiffness"),
            ));
        }
    }
    let its = names
        .iter()
        .position(|c| c == "newton_iterations")
        .ok_or("no newton_iterations column")?;
    Ok(Measured {
        iterations: rows[1..].iter().map(|r| r[its] as usize).collect(),
        cutbacks: summary.cutbacks,
        steps: summary.steps,
        seconds,
        outside: None,
    })
}

/// The ledger campaign of `seed` from case `first` (`ROBUST_LEDGER=1`): a range of cases of a seed
/// never run before, neither the CI range's nor a worked seed ([`WORKED_SEEDS`]), on a machine
/// whose sharing is stated.
fn start_ledger_campaign(seed: u64, first: usize, machine: Option<ledger::Machine>, only: bool) -> ledger::Campaign {
    assert!(
        !only,
        "ROBUST_LEDGER records a range of cases: ROBUST_ONLY's chosen cases make no campaign"
    );
    assert!(
        std::env::var_os("ROBUST_CASES").is_some() && std::env::var_os("ROBUST_SEED").is_some(),
        "ROBUST_LEDGER needs ROBUST_CASES and ROBUST_SEED"
    );
    let machine = machine.expect("ROBUST_LEDGER needs ROBUST_MACHINE=alone or shared, which sets the per-case limit");
    assert!(
        !WORKED_SEEDS.contains(&seed),
        "seed {seed}: the program was worked on against its cases ({WORKED_SEEDS:?}); draw another"
    );
    ledger::Campaign::start(seed, first, machine, DRAWS).unwrap_or_else(|e| panic!("{e}"))
}

fn env_number(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .map(|v| {
            v.parse()
                .unwrap_or_else(|_| panic!("{name} = {v}: allowed a whole number"))
        })
        .unwrap_or(default)
}

#[test]
fn random_cases_across_the_parameter_space_finish_with_the_energy_balanced_and_bounded_penetration() {
    // `ROBUST_ONLY=5,12` runs those cases of the seed (and counts them as a campaign)
    let only: Option<Vec<usize>> = std::env::var("ROBUST_ONLY").ok().map(|list| {
        list.split(',')
            .map(|i| {
                i.trim()
                    .parse()
                    .unwrap_or_else(|_| panic!("ROBUST_ONLY = {list}: allowed case numbers separated by commas"))
            })
            .collect()
    });
    let campaign = std::env::var_os("ROBUST_CASES").is_some() || only.is_some();
    let cases = only
        .as_ref()
        .map_or_else(|| env_number("ROBUST_CASES", CI_CASES as u64) as usize, Vec::len);
    let seed = env_number("ROBUST_SEED", 17);
    // the known open cases of the CI range: run briefly and reported, not asserted
    let known_open = |i: usize| !campaign && seed == 17 && KNOWN_OPEN.iter().any(|(k, _)| *k == i);
    let first = if only.is_some() {
        0
    } else {
        env_number("ROBUST_FIRST", 0) as usize
    };
    let machine = std::env::var("ROBUST_MACHINE").ok().map(|word| {
        ledger::Machine::parse(&word).unwrap_or_else(|| panic!("ROBUST_MACHINE = {word}: allowed alone or shared"))
    });
    let limit = machine.map_or(CASE_SECONDS, ledger::Machine::limit);
    let record = match std::env::var("ROBUST_LEDGER").ok().as_deref() {
        None => None,
        Some("1") => Some(start_ledger_campaign(seed, first, machine, only.is_some())),
        Some(v) => panic!("ROBUST_LEDGER = {v}: allowed 1"),
    };
    let root = common::scratch("cases");
    let next = AtomicUsize::new(first);
    let failures = Mutex::new(Vec::new());
    let measured = Mutex::new(Vec::new());
    let lines = Mutex::new(Vec::new());
    let started = std::time::Instant::now();
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let slot = next.fetch_add(1, Ordering::SeqCst);
                if slot >= first + cases {
                    break;
                }
                let index = only.as_ref().map_or(slot, |list| list[slot - first]);
                let began = std::time::Instant::now();
                let case = draw(seed, index);
                let limit = if known_open(index) { KNOWN_OPEN_SECONDS } else { limit };
                let result = run_case(&case, &root, limit);
                let line = |outcome, counts| ledger::CaseLine {
                    index,
                    wall: case.wall.to_string(),
                    outcome,
                    seconds: began.elapsed().as_secs_f64(),
                    counts,
                };
                let line = match result {
                    Ok(m) => {
                        let _ = std::fs::remove_dir_all(root.join(format!("case-{index}")));
                        let line = match m.outside {
                            Some(_) => line(ledger::Outcome::Refused, None),
                            None => line(
                                ledger::Outcome::Passed,
                                Some([
                                    m.steps,
                                    m.iterations.iter().sum(),
                                    m.iterations.iter().copied().max().unwrap_or(0),
                                    m.cutbacks,
                                ]),
                            ),
                        };
                        measured.lock().unwrap().push((index, m));
                        line
                    }
                    Err(failed) => {
                        eprintln!("case {index} FAILED: {}\n{}", failed.why, case.toml);
                        let line = line(failed.outcome, None);
                        failures.lock().unwrap().push((index, failed.why, case.toml));
                        line
                    }
                };
                if record.is_some() {
                    // the progress of a long campaign, for its log
                    eprintln!("case {index}: {} in {:.1} s", line.outcome.word(), line.seconds);
                }
                lines.lock().unwrap().push(line);
            });
        }
    });
    let measured = measured.into_inner().unwrap();
    let mut histogram = std::collections::BTreeMap::new();
    let mut cutback_cases = std::collections::BTreeMap::new();
    let (mut steps, mut slowest) = (0, (0.0f64, 0));
    for (index, m) in measured.iter().filter(|(_, m)| m.outside.is_none()) {
        for &i in &m.iterations {
            *histogram.entry(i).or_insert(0usize) += 1;
        }
        *cutback_cases.entry(m.cutbacks).or_insert(0usize) += 1;
        steps += m.steps;
        if m.seconds > slowest.0 {
            slowest = (m.seconds, *index);
        }
    }
    let outside: Vec<usize> = measured
        .iter()
        .filter(|(_, m)| m.outside.is_some())
        .map(|(i, _)| *i)
        .collect();
    let which = match &only {
        Some(list) => format!("{list:?}"),
        None => format!("from {first}"),
    };
    let wall_s = started.elapsed().as_secs_f64();
    let mut report = format!(
        "{} cases (seed {seed}, {which}) in {wall_s:.1} s: {} passed, {} refused as outside the model {outside:?}, \
         {} failed; {steps} steps; slowest passing case {} ({:.1} s)\n\
         Newton iterations per output step: {histogram:?}\ncut-backs per case: {cutback_cases:?}\n",
        cases,
        measured.len() - outside.len(),
        outside.len(),
        cases - measured.len(),
        slowest.1,
        slowest.0
    );
    let _ = std::fs::remove_dir_all(&root);
    let (known, failures): (Vec<_>, Vec<_>) = failures
        .into_inner()
        .unwrap()
        .into_iter()
        .partition(|(i, _, _)| known_open(*i));
    for (i, m) in &measured {
        if let Some(why) = &m.outside {
            // the cause, up to the advice that follows it
            let cause = why.split(". ").next().unwrap_or(why);
            report.push_str(&format!("case {i} outside the model: {cause}\n"));
        }
    }
    for (i, why, _) in &known {
        report.push_str(&format!("known open case {i} (issue 17): {why}\n"));
    }
    // the known open cases as configuration files, to be run with `pendulum-fem run --config`
    for (i, _, toml) in &known {
        report.push_str(&format!("--- known open case {i}\n{toml}"));
    }
    let open_passed: Vec<usize> = KNOWN_OPEN
        .iter()
        .map(|(k, _)| *k)
        .filter(|&k| (first..first + cases).contains(&k) && known_open(k) && !known.iter().any(|(i, _, _)| *i == k))
        .collect();
    if !open_passed.is_empty() {
        report.push_str(&format!("known open cases that passed this time: {open_passed:?}\n"));
    }
    for (i, why, _) in &failures {
        report.push_str(&format!("FAILED case {i}: {why}\n"));
    }
    // printed, and kept for CI's log (a passing test's output is captured)
    print!("{report}");
    let _ = std::fs::write(
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("robustness-report.txt"),
        &report,
    );
    if let Some(campaign) = &record {
        // recorded before the assertion, so that a campaign with failures has its row too
        let iterations = measured
            .iter()
            .filter(|(_, m)| m.outside.is_none())
            .flat_map(|(_, m)| m.iterations.iter().copied())
            .collect();
        let row = campaign
            .finish(lines.into_inner().unwrap(), iterations, wall_s)
            .unwrap_or_else(|e| panic!("the campaign's row was not recorded: {e}"));
        println!("ledger row:\n{}\n{}", ledger::HEADER, row.to_csv());
    }
    assert!(
        failures.is_empty(),
        "{} of {cases} cases failed:\n{}",
        failures.len(),
        failures
            .iter()
            .map(|(i, why, toml)| format!("--- case {i}: {why}\n{toml}"))
            .collect::<Vec<_>>()
            .join("\n")
    );
}

#[test]
fn the_case_generator_is_reproducible_and_its_configurations_are_valid() {
    for index in 0..200 {
        let (a, b) = (draw(17, index), draw(17, index));
        assert_eq!(a.toml, b.toml, "case {index} drawn twice differs");
        let cfg = Config::from_toml_str(&a.toml).unwrap_or_else(|e| panic!("case {index}: {e}\n{}", a.toml));
        // the drawn ranges are the ones the module doc states
        assert!((3e5..=2.1e11).contains(&cfg.material.youngs_modulus));
        assert!((-170.0..=170.0).contains(&cfg.initial.angle_deg));
        assert!((1e-3..=2e-2).contains(&cfg.time.dt));
    }
    assert_ne!(draw(17, 0).toml, draw(18, 0).toml, "the seed matters");
}

#[test]
fn after_a_blow_the_ringing_of_a_soft_head_converges_in_a_few_iterations_per_step() {
    // case 9 over its first impact: a Neo-Hookean head (E = 1.2e8 Pa) left ringing at strains
    // near 0.1, where the symmetric tangent alone, which leaves out the discrete gradient's
    // unsymmetric part, contracts slowly; Newton's updates corrected by GMRES on the system's own
    // Jacobian (`Solver::solve`) converge in a few iterations a step
    let case = draw(17, 9);
    let mut config = Config::from_toml_str(&case.toml).unwrap();
    config.time.end = 0.3;
    let out = common::scratch("ringing");
    let summary = run(&RunOptions {
        config,
        out: Some(out.clone()),
        force: true,
        observers: vec![pendulum_fem::render::pictures::attach()],
        ..Default::default()
    })
    .unwrap();
    assert_eq!(summary.cutbacks, 0);
    assert!(summary.energy_error <= ENERGY_BAR, "{}", summary.energy_error);
    let mut history = History::of_records(&read_records(&out.join("results.csv")).unwrap());
    history.set_impacts(&read_events(&out.join("events.csv")).unwrap());
    let end = history.impacts.first().expect("an impact").1;
    let (names, rows) = Table::read(&out.join("results.csv"))
        .map(|t| (t.names, t.rows))
        .unwrap();
    let (t, its) = (
        names.iter().position(|c| c == "time_s").unwrap(),
        names.iter().position(|c| c == "newton_iterations").unwrap(),
    );
    let after: Vec<f64> = rows.iter().filter(|r| r[t] > end + 1e-3).map(|r| r[its]).collect();
    assert!(after.len() >= 20, "{} steps after the impact", after.len());
    let mean = after.iter().sum::<f64>() / after.len() as f64;
    // at most 6.5 iterations a step on average (the first iteration of each step starts from a
    // guess that carries the ringing over)
    assert!(
        mean <= 6.5,
        "{mean:.2} Newton iterations per step after the impact: {after:?}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn the_campaign_ledger_is_well_formed_and_each_row_is_what_its_runs_file_gives() {
    let rows = ledger::read(&ledger::folder().join("ledger.csv")).unwrap_or_else(|e| panic!("{e}"));
    for row in &rows {
        assert!(!WORKED_SEEDS.contains(&row.seed), "seed {} is a worked seed", row.seed);
        let cases = ledger::read_runs(&ledger::runs_path(row.seed)).unwrap_or_else(|e| panic!("{e}"));
        ledger::check_against_runs(row, &cases).unwrap_or_else(|e| panic!("{e}"));
    }
    let runs = ledger::folder().join("runs");
    if runs.is_dir() {
        for entry in std::fs::read_dir(&runs).unwrap() {
            let path = entry.unwrap().path();
            let seed = path.file_stem().and_then(|s| s.to_str()?.parse::<u64>().ok());
            assert!(
                path.extension().is_some_and(|e| e == "csv") && seed.is_some_and(|s| rows.iter().any(|r| r.seed == s)),
                "{}: no campaign of the ledger",
                path.display()
            );
        }
    }
    println!(
        "cases since the last failure: {} ({} campaigns, {} cases in all)",
        ledger::since_last_failure(&rows),
        rows.len(),
        rows.iter().map(|r| r.figures.cases).sum::<usize>()
    );
}

#[test]
fn the_campaign_readme_quotes_the_ledgers_cases_since_the_last_failure() {
    let rows = ledger::read(&ledger::folder().join("ledger.csv")).unwrap_or_else(|e| panic!("{e}"));
    let quoted = ledger::quoted(&ledger::folder().join("README.md")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        quoted,
        ledger::since_last_failure(&rows),
        "tests/campaign/README.md quotes {quoted} cases since the last failure; the ledger gives another count"
    );
}

/// A ledger row of `seed` with `cases` cases of which `failures` failed, as the ledger holds it.
fn ledger_row(seed: u64, cases: usize, failures: usize) -> String {
    format!("2026-12-05T10:00:00Z,{seed},0,{cases},{failures},0,1188a41,120,shared,100.0,1.00,2.00,3.00,3,4,6,1,v1")
}

#[test]
fn cases_since_the_last_failure_are_those_of_the_rows_after_the_last_failing_one() {
    let rows = |list: &[(usize, usize)]| -> Vec<ledger::Row> {
        list.iter()
            .enumerate()
            .map(|(k, &(cases, failures))| ledger::Row::parse(&ledger_row(k as u64 + 100, cases, failures)).unwrap())
            .collect()
    };
    assert_eq!(ledger::since_last_failure(&rows(&[])), 0);
    assert_eq!(ledger::since_last_failure(&rows(&[(10, 0), (20, 0)])), 30);
    assert_eq!(
        ledger::since_last_failure(&rows(&[(10, 0), (20, 2), (30, 0), (40, 0)])),
        70
    );
    assert_eq!(ledger::since_last_failure(&rows(&[(10, 0), (20, 1)])), 0);
}

#[test]
fn a_ledger_row_reads_back_as_written_and_a_malformed_one_is_refused() {
    let passed = |index, seconds, counts| ledger::CaseLine {
        index,
        wall: "rigid".into(),
        outcome: ledger::Outcome::Passed,
        seconds,
        counts: Some(counts),
    };
    let cases = vec![
        passed(40, 3.25, [100, 420, 7, 0]),
        passed(41, 11.5, [300, 1500, 9, 2]),
        ledger::CaseLine {
            index: 42,
            wall: "none".into(),
            outcome: ledger::Outcome::Refused,
            seconds: 0.5,
            counts: None,
        },
        ledger::CaseLine {
            index: 43,
            wall: "deformable".into(),
            outcome: ledger::Outcome::Late,
            seconds: 120.3,
            counts: None,
        },
    ];
    let row = ledger::Row {
        date: ledger::utc(1_790_000_000),
        seed: 4242,
        first: 40,
        figures: ledger::Figures::of(&cases),
        commit: "1188a41+dirty".into(),
        limit_s: 120,
        machine: ledger::Machine::Shared,
        wall_s: 135.0,
        newton: Some([4, 6, 9]),
        draws: DRAWS.into(),
    };
    assert_eq!(
        (row.figures.cases, row.figures.failures, row.figures.refusals),
        (4, 1, 1)
    );
    assert_eq!(row.figures.case_s, Some([3.25, 11.5, 11.5]));
    assert_eq!(row.to_csv().split(',').count(), ledger::HEADER.split(',').count());
    assert_eq!(ledger::Row::parse(&row.to_csv()), Ok(row.clone()));
    ledger::check_against_runs(&row, &cases).unwrap();
    let fewer = &cases[..3];
    assert!(ledger::check_against_runs(&row, fewer).is_err(), "a case left out");
    for (bad, what) in [
        (ledger_row(1, 10, 11), "more failures than cases"),
        (
            ledger_row(1, 10, 0).replace(",120,shared,", ",60,shared,"),
            "a shared machine's limit is 120 s",
        ),
        (
            ledger_row(1, 10, 0).replace(",120,shared,", ",120,busy,"),
            "alone or shared",
        ),
        (
            ledger_row(1, 10, 0).replace("2026-12-05T10:00:00Z", "2026-12-05"),
            "a date and time",
        ),
        (
            ledger_row(1, 10, 0).replace(",3,4,6,", ",5,4,6,"),
            "a median above its 90th percentile",
        ),
        (ledger_row(1, 10, 0).replace(",v1", ","), "a draws version"),
        (ledger_row(1, 10, 0) + ",", "one cell too many"),
    ] {
        assert!(ledger::Row::parse(&bad).is_err(), "{what}: {bad}");
    }
    // a seed twice
    let path = common::scratch("ledger").join("ledger.csv");
    std::fs::write(
        &path,
        format!(
            "{}\n{}\n{}\n",
            ledger::HEADER,
            ledger_row(7, 10, 0),
            ledger_row(7, 5, 0)
        ),
    )
    .unwrap();
    assert!(ledger::read(&path).unwrap_err().contains("seed 7 twice"));
    std::fs::write(&path, format!("{}\n{}\n", ledger::HEADER, ledger_row(7, 10, 0))).unwrap();
    assert_eq!(ledger::read(&path).unwrap().len(), 1);
}

#[test]
fn the_ledgers_figures_are_values_of_the_list_at_their_nearest_rank() {
    let one_to_ten: Vec<usize> = (1..=10).collect();
    assert_eq!(ledger::spread(&one_to_ten), Some([5, 9, 10]));
    assert_eq!(ledger::spread(&[7]), Some([7, 7, 7]));
    assert_eq!(ledger::spread::<f64>(&[]), None);
}

#[test]
fn ledger_dates_are_utc_calendar_dates() {
    assert_eq!(ledger::utc(0), "1970-01-01T00:00:00Z");
    assert_eq!(ledger::utc(951_782_400), "2000-02-29T00:00:00Z");
    assert_eq!(ledger::utc(1_709_251_199), "2024-02-29T23:59:59Z");
    assert_eq!(ledger::utc(4_107_546_123), "2100-03-01T01:02:03Z");
}

#[test]
fn a_campaign_rewrites_the_readmes_quoted_count_and_no_other_line() {
    let path = common::scratch("quote").join("README.md");
    let text = format!("# Ledger\n\n{}**0**.\n\nThat is the sum.\n", ledger::QUOTE);
    std::fs::write(&path, &text).unwrap();
    assert_eq!(ledger::quoted(&path), Ok(0));
    ledger::quote(&path, 420).unwrap();
    assert_eq!(ledger::quoted(&path), Ok(420));
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        text.replace("**0**", "**420**")
    );
}
