//! `modes`: natural frequencies and mode shapes of the pinned pendulum, linearised about the
//! undeformed state.
//!
//! The problem is `K φ + Cᵀμ = ω² M φ`, `C φ = 0` ([`crate::modal`]): `K` the elastic tangent
//! stiffness at `u = 0` ([`modal::stiffness_at_rest`], the configured material law linearised:
//! plane stress or strain with the Lamé constants of `[material]`), `M` the consistent mass
//! matrix, `C` the hinge's two mean-displacement rows as in the dynamics. What is left out:
//!
//! * **gravity** (its prestress and the pendulum's restoring moment): the linearisation is about
//!   the undeformed, unloaded body, so the rigid rotation about the pivot is a 0 Hz mode. Its
//!   small-swing frequency under gravity, `√(m g d / I_O) / 2π`, is reported beside it.
//! * **the wall** (`[wall]`): a unilateral contact has no linearisation at the touching state,
//!   and a deformable block is a separate body. The modes are those of the pendulum alone; a
//!   configured wall is ignored with a note.
//! * **the torque** (`[torque]`): a load, not a stiffness at rest.
//!
//! `n` elastic modes are computed (1 to [`MAX_MODES`] = 50) besides the rigid one, by shift-invert
//! Lanczos about [`modal::rest_shift`]. Files in the output folder: `modes.json` (the table,
//! the checks and the timings), `modes.pvd` with `modes/mode_NN.vtu` (mode 0 the rigid rotation;
//! [`crate::render::modes`]) and `modes.png` (the first elastic modes). The command line picks the
//! folder as a run does ([`crate::commands::run::outdir::MODES_OUTPUTS`]): a fresh
//! `output.dir/modes-NNNN`, or `--out DIR`, refused when not empty unless `--force`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::commands::run::outdir::names;
use crate::config::WallKind;
use crate::modal::{self, Modes};
use crate::render::modes::{write_modes_png, write_modes_pvd, ModeView};
use crate::{mesh, Config, Error, Model};

/// Largest number of elastic modes `--n` accepts: up to it the pairs pass the eigensolver's checks
/// (backward errors below their bar) on the project's meshes; beyond it the higher modes of the
/// default mesh fail the check although their Lanczos estimates count as converged.
pub const MAX_MODES: usize = 50;

/// One row of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeRow {
    /// Mode number: 0 the rigid rotation, 1, 2, … the elastic modes.
    pub number: usize,
    /// `ω²` \[rad²/s²\] (rounding level for the rigid mode).
    pub omega2: f64,
    /// `f` \[Hz\] (0 for the rigid mode).
    pub frequency_hz: f64,
    /// Whether this is the rigid rotation about the pivot.
    pub rigid: bool,
    /// Share of the mode's kinetic energy in the x (transverse to the hanging rod) component.
    pub x_fraction: f64,
    /// Short description.
    pub description: String,
}

/// What `modes` computed.
#[derive(Clone, Debug)]
pub struct ModesReport {
    /// The table: the rigid mode, then the elastic ones.
    pub rows: Vec<ModeRow>,
    /// Unknowns of the problem (two per node).
    pub unknowns: usize,
    /// Triangles of the mesh.
    pub triangles: usize,
    /// The shift of the shift-invert iteration \[rad²/s²\].
    pub shift: f64,
    /// Largest backward error, deviation from `M`-orthonormality and relative hinge violation of
    /// the pairs ([`modal::verify`]).
    pub checks: [f64; 3],
    /// Whether a configured wall was left out.
    pub wall_ignored: bool,
    /// Small-swing frequency of the rigid pendulum under gravity \[Hz\] (0 without gravity).
    pub gravity_swing_hz: f64,
    /// Time of the mesh \[s\].
    pub seconds_mesh: f64,
    /// Time of the model set-up (pattern, mass matrix) and the stiffness \[s\].
    pub seconds_setup: f64,
    /// Time of the eigensolver (factorisation, Lanczos, checks) \[s\].
    pub seconds_eigen: f64,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// The configuration of the modal problem: the pendulum of `cfg` without a wall (see the module
/// doc); `true` when a wall was removed.
pub fn pendulum_alone(cfg: &Config) -> (Config, bool) {
    let mut c = cfg.clone();
    let wall = c.wall.kind != WallKind::None;
    c.wall.kind = WallKind::None;
    (c, wall)
}

/// Checks `n` (elastic modes) against `1..=MAX_MODES`.
pub fn check_count(n: usize) -> Result<(), Error> {
    if n == 0 || n > MAX_MODES {
        return Err(Error::Input(format!(
            "modes --n {n}: allowed 1 to {MAX_MODES} (the number of elastic modes besides the rigid rotation)"
        )));
    }
    Ok(())
}

/// The model of the pendulum of `cfg` alone, its stiffness at rest and the lowest `count`
/// eigenpairs (the rigid mode included), with the times of the three stages.
pub struct Computed {
    /// The model (no wall).
    pub model: Model,
    /// `K` at rest.
    pub stiffness: Vec<f64>,
    /// The hinge rows.
    pub constraints: Vec<Vec<f64>>,
    /// The eigenpairs.
    pub modes: Modes,
    /// The shift used.
    pub shift: f64,
    /// Mesh, set-up and eigensolver times \[s\].
    pub seconds: [f64; 3],
}

/// Meshes the pendulum of `cfg` (its wall removed), builds the model and computes `count`
/// eigenpairs.
pub fn compute(cfg: &Config, count: usize) -> Result<Computed, Error> {
    let (cfg, _) = pendulum_alone(cfg);
    let t0 = Instant::now();
    let mesh = mesh::generate(&cfg)?;
    let t1 = Instant::now();
    let model = Model::new(&cfg, mesh)?;
    let stiffness = modal::stiffness_at_rest(&model);
    let constraints = model.hinge.dense_rows(model.pattern.n).to_vec();
    let t2 = Instant::now();
    let shift = modal::rest_shift(&model);
    let modes = modal::constrained_modes(&model.pattern, &stiffness, &model.mass, &constraints, count, shift)?;
    let t3 = Instant::now();
    Ok(Computed {
        model,
        stiffness,
        constraints,
        modes,
        shift,
        seconds: [
            (t1 - t0).as_secs_f64(),
            (t2 - t1).as_secs_f64(),
            (t3 - t2).as_secs_f64(),
        ],
    })
}

/// Share of `φᵀMφ` in the x components.
fn x_fraction(c: &Computed, phi: &[f64]) -> f64 {
    let only_x: Vec<f64> = phi
        .iter()
        .enumerate()
        .map(|(i, v)| if i % 2 == 0 { *v } else { 0.0 })
        .collect();
    let mut m = vec![0.0; phi.len()];
    c.model.mass.apply(&only_x, &mut m);
    let x: f64 = only_x.iter().zip(&m).map(|(a, b)| a * b).sum();
    c.model.mass.apply(phi, &mut m);
    let all: f64 = phi.iter().zip(&m).map(|(a, b)| a * b).sum();
    if all > 0.0 {
        x / all
    } else {
        0.0
    }
}

/// The description of an elastic mode from its x share.
fn describe(x: f64) -> String {
    if x >= 0.7 {
        format!("mostly transverse (x {:.0} %)", 100.0 * x)
    } else if x <= 0.3 {
        format!("mostly along the rod (y {:.0} %)", 100.0 * (1.0 - x))
    } else {
        format!("mixed (x {:.0} %, y {:.0} %)", 100.0 * x, 100.0 * (1.0 - x))
    }
}

/// Small-swing frequency of the rigid pendulum under gravity \[Hz\]: `√(m g d / I_O) / 2π`.
fn gravity_swing_hz(model: &Model) -> f64 {
    let p = &model.projection;
    let d = (p.first_moment[0] / p.area).hypot(p.first_moment[1] / p.area);
    let k = model.mass_kg() * model.config.gravity.g.abs() * d / model.inertia_pivot();
    k.sqrt() / (2.0 * std::f64::consts::PI)
}

/// Computes `n` elastic modes of the pendulum of `cfg` and writes the files into `out_dir`
/// (created if needed); see the module doc.
pub fn modes_command(cfg: &Config, n: usize, out_dir: &Path) -> Result<ModesReport, Error> {
    check_count(n)?;
    let (_, wall_ignored) = pendulum_alone(cfg);
    let c = compute(cfg, n + 1)?;
    let scale = modal::eigenvalue_scale(&c.model.pattern, &c.stiffness, &c.model.mass);
    let rigid = c.modes.rigid_count(scale);
    if rigid != 1 {
        return Err(Error::Modal(format!(
            "expected one rigid mode (the rotation about the pivot), found {rigid} eigenvalues at rounding level \
             (|ω²| <= {:.3e} rad²/s²); the lowest are {:?}",
            modal::RIGID_TOLERANCE * scale,
            &c.modes.eigenvalues[..c.modes.eigenvalues.len().min(3)]
        )));
    }
    let swing = gravity_swing_hz(&c.model);
    let hz = c.modes.frequencies_hz();
    let rows: Vec<ModeRow> = c
        .modes
        .eigenvalues
        .iter()
        .zip(&c.modes.shapes)
        .enumerate()
        .map(|(i, (&l, phi))| {
            let x = x_fraction(&c, phi);
            ModeRow {
                number: i,
                omega2: l,
                frequency_hz: if i == 0 { 0.0 } else { hz[i] },
                rigid: i == 0,
                x_fraction: x,
                description: if i == 0 {
                    format!("rigid rotation about the pivot (under gravity: small swings at {swing:.4} Hz)")
                } else {
                    describe(x)
                },
            }
        })
        .collect();
    let checks = modal::verify(&c.model.pattern, &c.stiffness, &c.model.mass, &c.constraints, &c.modes);
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let mesh = &c.model.mesh;
    let views: Vec<ModeView<'_>> = rows
        .iter()
        .zip(&c.modes.shapes)
        .map(|(r, s)| ModeView {
            number: r.number,
            omega2: r.omega2,
            frequency_hz: r.frequency_hz,
            shape: s,
        })
        .collect();
    let mut files = write_modes_pvd(out_dir, mesh, &views)?;
    let png = out_dir.join(names::MODES_PNG);
    write_modes_png(&png, mesh, &views[1..])?;
    files.push(png);
    let mut report = ModesReport {
        rows,
        unknowns: c.model.pattern.n,
        triangles: mesh.triangles.len(),
        shift: c.shift,
        checks,
        wall_ignored,
        gravity_swing_hz: swing,
        seconds_mesh: c.seconds[0],
        seconds_setup: c.seconds[1],
        seconds_eigen: c.seconds[2],
        files,
    };
    let json = out_dir.join(names::MODES_JSON);
    let text = serde_json::to_string_pretty(&report.to_json()).expect("JSON of numbers and strings");
    crate::store::write_atomically(&json, |w| writeln!(w, "{text}"))?;
    report.files.insert(0, json);
    Ok(report)
}

impl ModesReport {
    /// The report as JSON: `modes` (one object per row: `mode`, `omega2_rad2_s2`,
    /// `frequency_hz`, `rigid`, `x_fraction`, `description`), `unknowns`, `triangles`,
    /// `shift_rad2_s2`, `checks` (`residual`, `orthonormality`, `constraint`), `wall`
    /// (`"none"` or `"ignored"`), `gravity_swing_hz`, `seconds` (`mesh`, `setup`, `eigen`).
    pub fn to_json(&self) -> serde_json::Value {
        let modes: Vec<serde_json::Value> = self
            .rows
            .iter()
            .map(|r| {
                serde_json::json!({
                    "mode": r.number,
                    "omega2_rad2_s2": r.omega2,
                    "frequency_hz": r.frequency_hz,
                    "rigid": r.rigid,
                    "x_fraction": r.x_fraction,
                    "description": r.description,
                })
            })
            .collect();
        serde_json::json!({
            "modes": modes,
            "unknowns": self.unknowns,
            "triangles": self.triangles,
            "shift_rad2_s2": self.shift,
            "checks": {
                "residual": self.checks[0],
                "orthonormality": self.checks[1],
                "constraint": self.checks[2],
            },
            "wall": if self.wall_ignored { "ignored" } else { "none" },
            "gravity_swing_hz": self.gravity_swing_hz,
            "seconds": {
                "mesh": self.seconds_mesh,
                "setup": self.seconds_setup,
                "eigen": self.seconds_eigen,
            },
        })
    }

    /// The table printed on stdout.
    pub fn table(&self) -> String {
        let mut s = format!(
            "natural frequencies of the pinned pendulum about the undeformed state ({} triangles, {} unknowns)\n",
            self.triangles, self.unknowns
        );
        if self.wall_ignored {
            s.push_str("note: the configured wall is left out: these are the modes of the pendulum alone\n");
        }
        s.push_str(&format!(
            "{:>4}  {:>16}  {:>12}  {}\n",
            "mode", "omega^2 [rad²/s²]", "f [Hz]", "description"
        ));
        for r in &self.rows {
            let f = if r.rigid {
                "0".to_string()
            } else {
                format!("{:.3}", r.frequency_hz)
            };
            s.push_str(&format!(
                "{:>4}  {:>16.6e}  {:>12}  {}\n",
                r.number, r.omega2, f, r.description
            ));
        }
        s.push_str(&format!(
            "checks: backward error {:.1e}, M-orthonormality {:.1e}, hinge {:.1e}; eigensolver {:.3} s (mesh {:.3} s, \
             set-up {:.3} s)\n",
            self.checks[0], self.checks[1], self.checks[2], self.seconds_eigen, self.seconds_mesh, self.seconds_setup
        ));
        s
    }
}
