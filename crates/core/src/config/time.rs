//! The `[time]` section (the step, the end and the integration scheme) and the `[solver]` section
//! (Newton's tolerances, iterations and cut-backs, [`Cutbacks`]), with their rules.

use serde::{Deserialize, Serialize};

use super::ranges::{non_negative, positive, range, within, Mistakes};

/// Time integration scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scheme {
    /// The energy-momentum scheme ([`crate::scheme::energy_momentum`]): the midpoint rule with a discrete
    /// gradient; conserves the total energy and the angular momentum about the pivot exactly at any
    /// step size (with `time.dissipation = 0`). The default.
    EnergyMomentum,
    /// Newmark average acceleration (β = ¼, γ = ½), the tutorial's scheme: second order, no
    /// numerical dissipation.
    Trapezoidal,
    /// Hilber–Hughes–Taylor α: second order, damps the unresolved stiff elastic modes (spectral
    /// radius (1 + α)/(1 − α) at infinite frequency). For fast spins, where the trapezoidal rule
    /// lets the rotation pump energy into those modes.
    Hht,
}

impl Scheme {
    /// The name in the configuration.
    pub fn name(self) -> &'static str {
        match self {
            Self::EnergyMomentum => "energy-momentum",
            Self::Trapezoidal => "trapezoidal",
            Self::Hht => "hht",
        }
    }
}

/// Time stepping.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Time {
    /// Time step \[s\].
    pub dt: f64,
    /// End time \[s\].
    pub end: f64,
    /// Integration scheme.
    pub scheme: Scheme,
    /// α of the HHT scheme, −1/3 ≤ α ≤ 0 (0 is the trapezoidal rule). Only `scheme = "hht"` uses
    /// it: the other schemes silently ignore it (it is range-checked all the same).
    pub hht_alpha: f64,
    /// Numerical dissipation `χ` of the energy-momentum scheme, `0 ≤ χ < 1`: the strain energy
    /// loses `(χ/2) ΔE:ℂ₀:ΔE` per step, the angular momentum is still conserved; the spectral radius
    /// of the unresolved elastic modes is `(1 − χ)/(1 + χ)`. 0: exact conservation.
    pub dissipation: f64,
    /// Largest rotation of the body in one internal sub-step of the Newmark schemes
    /// (`"trapezoidal"`, `"hht"`) \[deg\]: a step whose predicted rotation is larger is split into 2,
    /// 4, 8, … equal sub-steps (rows stay at multiples of `dt`). The energy-momentum scheme needs no
    /// sub-steps and silently ignores it (it is range-checked all the same).
    pub max_rotation_deg: f64,
}

impl Default for Time {
    fn default() -> Self {
        Self {
            dt: 0.01,
            end: 1.0,
            scheme: Scheme::EnergyMomentum,
            hht_alpha: -0.05,
            dissipation: 0.0,
            max_rotation_deg: 3.0,
        }
    }
}

/// The steps of a run: `full` steps of `time.dt`, then, when `time.end` is not a multiple of
/// `time.dt` (to 1e-9 relative), one shorter `last` step that lands exactly on `time.end`.
/// `time.end = 0.015` with `dt = 0.01`: one step to 0.01, one of 0.005 to 0.015.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepPlan {
    /// Steps of `time.dt`.
    pub full: usize,
    /// Length of the shortened last step \[s\], if any.
    pub last: Option<f64>,
}

impl StepPlan {
    /// The plan of a time section.
    pub fn of(time: &Time) -> Self {
        let x = time.end / time.dt;
        let n = x.round();
        if (x - n).abs() <= 1e-9 * x.max(1.0) {
            Self {
                full: n as usize,
                last: None,
            }
        } else {
            let full = x.floor();
            Self {
                full: full as usize,
                last: Some(time.end - full * time.dt),
            }
        }
    }

    /// Steps in all.
    pub fn steps(&self) -> usize {
        self.full + usize::from(self.last.is_some())
    }
}

impl Time {
    /// The steps of a run of this section ([`StepPlan`]).
    pub fn plan(&self) -> StepPlan {
        StepPlan::of(self)
    }

    /// Number of steps of a run: [`StepPlan::steps`] (a shortened last step counts).
    pub fn steps(&self) -> usize {
        self.plan().steps()
    }

    /// The `[time]` rules.
    pub(super) fn validate(&self, m: &mut Mistakes) {
        let dt = m.check(positive("time.dt", self.dt, "s"));
        let end = m.check(non_negative("time.end", self.end, "s"));
        m.check(within("time.hht_alpha", self.hht_alpha, -1.0 / 3.0, 0.0, ""));
        if !(self.dissipation >= 0.0 && self.dissipation < 1.0) {
            m.keep(range(
                "time.dissipation",
                self.dissipation,
                "0 <= dissipation < 1 (0: exact energy conservation)",
            ));
        } else if self.dissipation != 0.0 && self.scheme != Scheme::EnergyMomentum {
            m.push(
                "time.dissipation",
                format!(
                    "time.dissipation = {}: it belongs to time.scheme = \"energy-momentum\" (the Newmark schemes \
                     have time.hht_alpha with time.scheme = \"hht\" instead)",
                    self.dissipation
                ),
            );
        }
        m.check(within("time.max_rotation_deg", self.max_rotation_deg, 0.1, 90.0, "deg"));
        if !(dt && end) {
            return;
        }
        if self.end > 0.0 && self.dt > self.end {
            m.keep(range(
                "time.dt",
                self.dt,
                &format!("0 < dt <= time.end = {} s", self.end),
            ));
        } else if self.steps() > 10_000_000 {
            m.push(
                "time.end",
                format!(
                    "time.end / time.dt = {:.0} steps: at most 10000000 steps are allowed",
                    self.end / self.dt
                ),
            );
        }
    }
}

/// Newton solver settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Solver {
    /// Convergence threshold on the energy norm of the Newton update, `|Δuᵀ r|` \[J\].
    pub tolerance: f64,
    /// Energy-momentum scheme: largest energy error of one step, relative to the step's energy
    /// scale (kinetic energy + weight × largest radius + π |torque|,
    /// [`crate::scheme::energy_momentum::energy_scale`]). The energy error of a step is exactly
    /// `½ Δu · r(u₁)`, the work of the remaining residual, so this bounds the drift of a run of `n`
    /// steps by `n ×` this value.
    pub energy_tolerance: f64,
    /// Newton iterations allowed per step (default 40). The tutorial's swing converges in 2–4; a
    /// soft head pressed against a stiff contact converges in 10–40 per impact sub-step
    /// (contractions of 0.5–0.9 per iteration; why is open, see `tests/robustness.rs`), and
    /// halving such a step does not reduce them: with a lower limit such a sub-step is halved again
    /// and again (seed 18's case 5 of `tests/robustness.rs`, E = 3 MPa against k = 1.6e12 N/m³,
    /// needs 25 in a sub-step of its first impact). A step that fails for another reason (an
    /// indefinite tangent, a line search that cannot proceed) fails as it would with a lower limit.
    pub max_iterations: usize,
    /// How often a failed step may be halved and retried (see [`Cutbacks`]).
    pub max_cutbacks: Cutbacks,
}

/// How often a failed step may be halved and retried: `"auto"` (the default) or a count 0–30.
///
/// **`"auto"`**: at least [`Cutbacks::AUTO_MIN`] times, and beyond that for as long as the step is
/// longer than the mesh's wave time ([`crate::simulation::Model::wave_time`], the time a pressure
/// wave takes to cross the thinnest element at its node spacing), at most 30 times. A step that
/// short resolves every motion the mesh can carry, and its inertia outweighs the elements'
/// stiffness, so a step that still fails there fails for a reason other than its length. Why not
/// a fixed count: a soft plate driven hard can go through a fast local event, such as the edge
/// of its rod compressed to a principal stretch of 0.55–0.73 (depending on the mesh) at the
/// re-entrant corner where the rod meets the head (seed 18's case 12 of `tests/robustness.rs`:
/// E = 2.5 MPa, a 0.28 kg head rebounding from the wall against 0.75 N·m), that a step resolves
/// only at about the time a wave crosses an element there. That case needed seven halvings of
/// its 2.6 ms step (20 µs) where six were allowed, and failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cutbacks {
    /// Down to the mesh's wave time (at least [`Cutbacks::AUTO_MIN`] halvings, at most 30).
    Auto,
    /// Exactly this many halvings at most.
    Count(usize),
}

impl Cutbacks {
    /// Halvings `"auto"` always allows (the former fixed default).
    pub const AUTO_MIN: usize = 6;
    /// The largest count (2⁻³⁰ of a step).
    pub const MAX: usize = 30;

    /// The message refusing `value` for `solver.max_cutbacks`.
    fn refusal(value: impl std::fmt::Display) -> String {
        format!("solver.max_cutbacks = {value}: allowed \"auto\" or 0 to {}", Self::MAX)
    }

    /// Whether a failed step of length `dt`, already halved `depth` times, may be halved again, with
    /// the mesh's wave time `wave_time` \[s\].
    pub fn allows(self, depth: usize, dt: f64, wave_time: f64) -> bool {
        match self {
            Self::Count(n) => depth < n,
            Self::Auto => depth < Self::AUTO_MIN || (dt > wave_time && depth < Self::MAX),
        }
    }
}

impl Serialize for Cutbacks {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Auto => serializer.serialize_str("auto"),
            Self::Count(n) => serializer.serialize_u64(*n as u64),
        }
    }
}

impl<'de> Deserialize<'de> for Cutbacks {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = Cutbacks;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "\"auto\" or a count from 0 to {}", Cutbacks::MAX)
            }
            // a count's range is checked with the other rules ([`Solver::validate`])
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Cutbacks, E> {
                usize::try_from(v)
                    .map(Cutbacks::Count)
                    .map_err(|_| E::custom(Cutbacks::refusal(v)))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Cutbacks, E> {
                usize::try_from(v)
                    .map(Cutbacks::Count)
                    .map_err(|_| E::custom(Cutbacks::refusal(v)))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Cutbacks, E> {
                match v {
                    "auto" => Ok(Cutbacks::Auto),
                    _ => Err(E::custom(Cutbacks::refusal(format!("{v:?}")))),
                }
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

impl Default for Solver {
    fn default() -> Self {
        Self {
            tolerance: 1e-6,
            energy_tolerance: 1e-12,
            max_iterations: 40,
            max_cutbacks: Cutbacks::Auto,
        }
    }
}

impl Solver {
    /// The `[solver]` rules.
    pub(super) fn validate(&self, m: &mut Mistakes) {
        let s = self;
        if !(s.tolerance > 0.0 && s.tolerance.is_finite()) {
            m.keep(range("solver.tolerance", s.tolerance, "tolerance > 0 (J)"));
        }
        if !(s.energy_tolerance > 0.0 && s.energy_tolerance <= 1e-3) {
            m.keep(range(
                "solver.energy_tolerance",
                s.energy_tolerance,
                "0 < energy_tolerance <= 1e-3 (relative energy error per step)",
            ));
        }
        if !(1..=1000).contains(&s.max_iterations) {
            m.push(
                "solver.max_iterations",
                format!("solver.max_iterations = {}: allowed range 1 to 1000", s.max_iterations),
            );
        }
        if let Cutbacks::Count(n) = s.max_cutbacks {
            if n > Cutbacks::MAX {
                m.push("solver.max_cutbacks", Cutbacks::refusal(n));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;

    #[test]
    fn the_time_scheme_keys_are_checked_with_their_ranges() {
        let cfg = Config::load(None, &["time.dissipation=0.3".into()]).unwrap();
        assert_eq!((cfg.time.scheme, cfg.time.dissipation), (Scheme::EnergyMomentum, 0.3));
        for (set, needles) in [
            (
                vec!["time.dissipation=1"],
                vec!["time.dissipation", "0 <= dissipation < 1"],
            ),
            (
                vec!["time.dissipation=-0.1"],
                vec!["time.dissipation", "0 <= dissipation < 1"],
            ),
            (
                vec!["time.dissipation=0.2", "time.scheme=\"trapezoidal\""],
                vec!["time.dissipation", "energy-momentum"],
            ),
            (
                vec!["solver.energy_tolerance=0"],
                vec!["solver.energy_tolerance", "0 < energy_tolerance"],
            ),
            (vec!["time.scheme=\"midpoint\""], vec!["time.scheme"]),
        ] {
            let sets: Vec<String> = set.iter().map(|s| s.to_string()).collect();
            let err = Config::load(None, &sets).unwrap_err().to_string();
            for n in needles {
                assert!(err.contains(n), "{set:?}: `{n}` missing in {err}");
            }
        }
    }
}
