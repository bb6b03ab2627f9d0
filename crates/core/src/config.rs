//! Run configuration: every tunable with its default, unit and allowed range.
//!
//! The configuration is TOML. Every key is optional; the defaults are the model of the NGSolve
//! tutorial "FEM Pendulum: Basics" stepped by the energy-momentum scheme from the rigid-body start
//! (`time.scheme = "trapezoidal"` with `initial.acceleration = "zero"` is the tutorial's run).
//! Unknown keys are errors (serde `deny_unknown_fields`) naming the line and the nearest allowed
//! key, and every value is range-checked by [`Config::validate`], whose messages name the key
//! (`mesh.max_size`) and the allowed range. Overrides from the command line (`--set mesh.max_size=0.01`) are merged into the
//! TOML document before it is deserialised, so they are checked exactly like file values.
//!
//! All quantities are SI: metres, kilograms, seconds, pascals, newtons, radians unless a key says
//! `_deg`.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use crate::error::Error;

/// The whole configuration, one section per pipeline stage.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Config {
    /// Shape of the pendulum.
    pub geometry: Geometry,
    /// Mesh sizes and element order.
    pub mesh: MeshConfig,
    /// Constitutive law and its parameters.
    pub material: Material,
    /// Gravity.
    pub gravity: Gravity,
    /// Initial state.
    pub initial: Initial,
    /// Time stepping.
    pub time: Time,
    /// Newton solver.
    pub solver: Solver,
    /// Actuator torque at the pivot.
    pub torque: Torque,
    /// The wall the head strikes (the contact tutorial).
    pub wall: Wall,
    /// Contact between the head and the wall.
    pub contact: Contact,
    /// What a run writes.
    pub output: Output,
}

/// Pendulum geometry (the tutorial's `r_rod`, `r_head`, `r_hole`, `l_center`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Geometry {
    /// Half-width of the rod \[m\].
    pub rod_half_width: f64,
    /// Outer radius of the head \[m\].
    pub head_radius: f64,
    /// Radius of the hole in the head \[m\]; 0 means no hole.
    pub hole_radius: f64,
    /// Distance from the pivot to the head centre \[m\].
    pub head_center_distance: f64,
    /// Out-of-plane thickness \[m\].
    pub thickness: f64,
}

impl Default for Geometry {
    fn default() -> Self {
        Self {
            rod_half_width: 0.015,
            head_radius: 0.06,
            hole_radius: 0.03,
            head_center_distance: 0.24,
            thickness: 0.01,
        }
    }
}

impl Geometry {
    /// The `[geometry]` rules: positive sizes, the hole inside the head, the rod narrower than
    /// the head and with a free length.
    fn validate(&self) -> Result<(), Error> {
        let g = self;
        positive("geometry.rod_half_width", g.rod_half_width, "m")?;
        positive("geometry.head_radius", g.head_radius, "m")?;
        non_negative("geometry.hole_radius", g.hole_radius, "m")?;
        positive("geometry.head_center_distance", g.head_center_distance, "m")?;
        positive("geometry.thickness", g.thickness, "m")?;
        if g.hole_radius >= g.head_radius {
            return Err(range(
                "geometry.hole_radius",
                g.hole_radius,
                &format!(
                    "0 <= hole_radius < head_radius = {} m (the hole must lie inside the head)",
                    g.head_radius
                ),
            ));
        }
        if g.rod_half_width >= g.head_radius {
            return Err(range(
                "geometry.rod_half_width",
                g.rod_half_width,
                &format!(
                    "0 < rod_half_width < head_radius = {} m (the rod must be narrower than the head)",
                    g.head_radius
                ),
            ));
        }
        // The rod [−r, r] × [0, l] must reach into the head disc and must not end inside the hole:
        // its end meets the head circle at distance l − sqrt(R² − r²) from the pivot, which must be > 0,
        // and the rod end (the head centre) lies in the hole, so the rod's sides must meet the head ring
        // outside the hole: sqrt(R² − r²) > sqrt(max(h² − r², 0)) holds whenever R > h.
        let reach = (g.head_radius * g.head_radius - g.rod_half_width * g.rod_half_width).sqrt();
        if g.head_center_distance <= reach {
            return Err(range(
                "geometry.head_center_distance",
                g.head_center_distance,
                &format!(
                    "head_center_distance > sqrt(head_radius² − rod_half_width²) = {reach:.6} m \
                     (the head would swallow the pivot; the rod must have a free length)"
                ),
            ));
        }
        Ok(())
    }
}

/// Mesh sizes. The local sizes default to the tutorial's fractions of the geometry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MeshConfig {
    /// Global maximum element size \[m\].
    pub max_size: f64,
    /// Geometric order: 1 (straight-sided) or 2 (curved six-node triangles on the circles).
    pub order: u32,
    /// Size in the rod \[m\]; default `rod_half_width / 2`.
    pub rod_size: Option<f64>,
    /// Size in the head \[m\]; default `head_radius / 5`.
    pub head_size: Option<f64>,
    /// Size along the hinge edge \[m\]; default `rod_half_width / 10`.
    pub hinge_edge_size: Option<f64>,
    /// Size at the two hinge corners \[m\]; default `rod_half_width / 20`.
    pub hinge_corner_size: Option<f64>,
    /// Size along the head and hole circles \[m\]; default `head_radius / 20`.
    pub circle_edge_size: Option<f64>,
    /// Growth rate of the size away from small features (Netgen's `grading`), 0.05 to 1.
    pub grading: f64,
    /// Divides every size above (the global maximum and each local size, given or derived):
    /// 2 halves them all (the default pendulum: 1233 → 3436 triangles). 0.1 to 100.
    pub refine: f64,
    /// A Gmsh 4.1 mesh to swing instead of the generated pendulum (ASCII or binary, 3- or 6-node
    /// triangles, the hinge edge in a physical curve group named `rotation`); the geometry and
    /// the sizes above are then unused, except `geometry.thickness`.
    pub file: Option<PathBuf>,
}

impl Default for MeshConfig {
    fn default() -> Self {
        Self {
            max_size: 0.03,
            order: 2,
            rod_size: None,
            head_size: None,
            hinge_edge_size: None,
            hinge_corner_size: None,
            circle_edge_size: None,
            grading: 0.3,
            refine: 1.0,
            file: None,
        }
    }
}

/// Local mesh sizes with the geometry-derived defaults filled in \[m\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshSizes {
    /// Global maximum.
    pub max_size: f64,
    /// In the rod.
    pub rod: f64,
    /// In the head.
    pub head: f64,
    /// Along the hinge edge.
    pub hinge_edge: f64,
    /// At the hinge corners.
    pub hinge_corner: f64,
    /// Along the circles.
    pub circle_edge: f64,
    /// Growth rate away from small features.
    pub grading: f64,
}

impl Config {
    /// The local mesh sizes, with defaults derived from the geometry as in the tutorial, each
    /// divided by `mesh.refine`.
    pub fn mesh_sizes(&self) -> MeshSizes {
        self.mesh.sizes(&self.geometry)
    }
}

impl MeshConfig {
    /// The local mesh sizes for geometry `g` ([`Config::mesh_sizes`]).
    fn sizes(&self, g: &Geometry) -> MeshSizes {
        let m = self;
        let r = m.refine;
        MeshSizes {
            max_size: m.max_size / r,
            rod: m.rod_size.unwrap_or(g.rod_half_width / 2.0) / r,
            head: m.head_size.unwrap_or(g.head_radius / 5.0) / r,
            hinge_edge: m.hinge_edge_size.unwrap_or(g.rod_half_width / 10.0) / r,
            hinge_corner: m.hinge_corner_size.unwrap_or(g.rod_half_width / 20.0) / r,
            circle_edge: m.circle_edge_size.unwrap_or(g.head_radius / 20.0) / r,
            grading: m.grading,
        }
    }

    /// The `[mesh]` rules (the smallest size relative to the geometry `g`).
    fn validate(&self, g: &Geometry) -> Result<(), Error> {
        let m = self;
        positive("mesh.max_size", m.max_size, "m")?;
        if !(m.order == 1 || m.order == 2) {
            return Err(Error::Config(format!(
                "mesh.order = {}: allowed values are 1 and 2",
                m.order
            )));
        }
        for (key, v) in [
            ("mesh.rod_size", m.rod_size),
            ("mesh.head_size", m.head_size),
            ("mesh.hinge_edge_size", m.hinge_edge_size),
            ("mesh.hinge_corner_size", m.hinge_corner_size),
            ("mesh.circle_edge_size", m.circle_edge_size),
        ] {
            if let Some(v) = v {
                positive(key, v, "m")?;
            }
        }
        within("mesh.grading", m.grading, 0.05, 1.0, "")?;
        within("mesh.refine", m.refine, 0.1, 100.0, "(divides every mesh size)")?;
        let sizes = self.sizes(g);
        let smallest = [
            sizes.max_size,
            sizes.rod,
            sizes.head,
            sizes.hinge_edge,
            sizes.hinge_corner,
            sizes.circle_edge,
        ]
        .into_iter()
        .fold(f64::INFINITY, f64::min);
        let scale = g.head_center_distance + g.head_radius;
        if smallest < scale * 1e-5 {
            return Err(Error::Config(format!(
                "mesh sizes: the smallest local size {smallest:e} m is below 1e-5 × the pendulum length ({:e} m); \
                 allowed: sizes >= {:e} m",
                scale,
                scale * 1e-5
            )));
        }
        Ok(())
    }
}

/// Constitutive model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MaterialModel {
    /// The tutorial's compressible Neo-Hookean law, `ψ = μ/2 (tr C − 2) + μ²/λ (det C^(−λ/2μ) − 1)`.
    NeoHookean,
    /// St. Venant–Kirchhoff, `ψ = λ/2 (tr E)² + μ tr(E²)`.
    SaintVenantKirchhoff,
}

/// Two-dimensional reduction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Plane {
    /// Thin plate, `σ_zz = 0`: `λ* = Eν/(1 − ν²)`.
    Stress,
    /// Long body, `ε_zz = 0`: `λ = Eν/((1 + ν)(1 − 2ν))`.
    Strain,
}

/// Material parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Material {
    /// Constitutive model.
    pub model: MaterialModel,
    /// Young's modulus \[Pa\].
    pub youngs_modulus: f64,
    /// Poisson's ratio \[-\].
    pub poisson_ratio: f64,
    /// Mass density \[kg/m³\].
    pub density: f64,
    /// Plane stress or plane strain.
    pub plane: Plane,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            model: MaterialModel::NeoHookean,
            youngs_modulus: 2.1e11,
            poisson_ratio: 0.3,
            density: 7800.0,
            plane: Plane::Stress,
        }
    }
}

impl Material {
    /// Lamé parameters `(λ, μ)` of the 2-D model \[Pa\] (plane stress uses `λ*`).
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        let mu = e / (2.0 * (1.0 + nu));
        let lambda = match self.plane {
            Plane::Stress => e * nu / (1.0 - nu * nu),
            Plane::Strain => e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        };
        (lambda, mu)
    }

    /// The `[material]` rules.
    fn validate(&self) -> Result<(), Error> {
        let mat = self;
        positive("material.youngs_modulus", mat.youngs_modulus, "Pa")?;
        if !(mat.poisson_ratio > -1.0 && mat.poisson_ratio < 0.5) {
            return Err(range(
                "material.poisson_ratio",
                mat.poisson_ratio,
                "-1 < poisson_ratio < 0.5",
            ));
        }
        if mat.model == MaterialModel::NeoHookean && mat.poisson_ratio <= 0.0 {
            return Err(range(
                "material.poisson_ratio",
                mat.poisson_ratio,
                "0 < poisson_ratio < 0.5 for the neo-hookean model (its energy divides by λ)",
            ));
        }
        positive("material.density", mat.density, "kg/m^3")
    }
}

/// Gravity along −y.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Gravity {
    /// Magnitude \[m/s²\]; 0 switches gravity off.
    pub g: f64,
}

impl Default for Gravity {
    fn default() -> Self {
        Self { g: 9.81 }
    }
}

impl Gravity {
    /// The `[gravity]` rules.
    fn validate(&self) -> Result<(), Error> {
        non_negative("gravity.g", self.g, "m/s^2")
    }
}

/// How the initial acceleration is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum InitialAcceleration {
    /// Rigid-body acceleration `α₀ e_z × r − ω₀² r`, `α₀` from the torque balance about the pivot.
    Rigid,
    /// Zero, exactly as the tutorial starts.
    Zero,
}

/// The elastic state of the initial configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum InitialElastic {
    /// In elastic equilibrium with gravity, torque and the inertial forces of the rigid start
    /// (requires `acceleration = "rigid"`; the default there).
    Equilibrium,
    /// Undeformed (the tutorial's start; the default with `acceleration = "zero"`).
    Undeformed,
}

/// Initial state: a rigid rotation about the pivot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Initial {
    /// Initial angle \[deg\], counter-clockwise from hanging straight down.
    pub angle_deg: f64,
    /// Initial angular velocity \[rad/s\].
    pub angular_velocity: f64,
    /// Initial acceleration field.
    pub acceleration: InitialAcceleration,
    /// Elastic state of the start; `None`: equilibrium with a rigid start, undeformed with a zero one.
    pub elastic: Option<InitialElastic>,
}

impl Default for Initial {
    fn default() -> Self {
        Self {
            angle_deg: 20.0,
            angular_velocity: 0.0,
            acceleration: InitialAcceleration::Rigid,
            elastic: None,
        }
    }
}

impl Initial {
    /// The elastic state with its default filled in.
    pub fn elastic_state(&self) -> InitialElastic {
        self.elastic.unwrap_or(match self.acceleration {
            InitialAcceleration::Rigid => InitialElastic::Equilibrium,
            InitialAcceleration::Zero => InitialElastic::Undeformed,
        })
    }

    /// The `[initial]` rules.
    fn validate(&self) -> Result<(), Error> {
        within("initial.angle_deg", self.angle_deg, -360.0, 360.0, "deg")?;
        finite("initial.angular_velocity", self.angular_velocity)?;
        if self.elastic == Some(InitialElastic::Equilibrium) && self.acceleration == InitialAcceleration::Zero {
            return Err(Error::Config(
                "initial.elastic = \"equilibrium\" needs initial.acceleration = \"rigid\" (a tilted body with zero \
                 acceleration has no equilibrium); allowed with \"zero\": \"undeformed\""
                    .into(),
            ));
        }
        Ok(())
    }
}

/// Time integration scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scheme {
    /// The energy-momentum scheme ([`crate::energy_momentum`]): the midpoint rule with a discrete
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

impl Time {
    /// Number of steps, `round(end / dt)`.
    pub fn steps(&self) -> usize {
        (self.end / self.dt).round() as usize
    }

    /// The `[time]` rules.
    fn validate(&self) -> Result<(), Error> {
        positive("time.dt", self.dt, "s")?;
        non_negative("time.end", self.end, "s")?;
        within("time.hht_alpha", self.hht_alpha, -1.0 / 3.0, 0.0, "")?;
        if !(self.dissipation >= 0.0 && self.dissipation < 1.0) {
            return Err(range(
                "time.dissipation",
                self.dissipation,
                "0 <= dissipation < 1 (0: exact energy conservation)",
            ));
        }
        if self.dissipation != 0.0 && self.scheme != Scheme::EnergyMomentum {
            return Err(Error::Config(format!(
                "time.dissipation = {}: it belongs to time.scheme = \"energy-momentum\" (the Newmark schemes \
                 have time.hht_alpha with time.scheme = \"hht\" instead)",
                self.dissipation
            )));
        }
        within("time.max_rotation_deg", self.max_rotation_deg, 0.1, 90.0, "deg")?;
        if self.end > 0.0 && self.dt > self.end {
            return Err(range(
                "time.dt",
                self.dt,
                &format!("0 < dt <= time.end = {} s", self.end),
            ));
        }
        if self.steps() > 10_000_000 {
            return Err(Error::Config(format!(
                "time.end / time.dt = {:.0} steps: at most 10000000 steps are allowed",
                self.end / self.dt
            )));
        }
        Ok(())
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
    /// [`crate::energy_momentum::energy_scale`]). The energy error of a step is exactly
    /// `½ Δu · r(u₁)`, the work of the remaining residual, so this bounds the drift of a run of `n`
    /// steps by `n ×` this value.
    pub energy_tolerance: f64,
    /// Newton iterations allowed per step (default 40). The tutorial's swing converges in 2–4; a
    /// soft head pressed against a stiff contact converges in 10–40 per impact sub-step
    /// (contractions of 0.5–0.9 per iteration; why is open, see `tests/robustness.rs`), and
    /// halving such a step does not reduce them. With 20, a sub-step that needed 25 was halved
    /// again and again: seed 18's case 5 of `tests/robustness.rs` (E = 3 MPa against
    /// k = 1.6e12 N/m³) spent more than 118 s in its first impact; with 40 it takes 24.8 s and
    /// the whole run 99 s with one cut-back. A step that fails for another reason fails as before
    /// (an indefinite tangent, a line search that cannot proceed), and the campaign's twelve CI
    /// cases took 218.6 s instead of 226.9 s.
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
    fn validate(&self) -> Result<(), Error> {
        let s = self;
        if !(s.tolerance > 0.0 && s.tolerance.is_finite()) {
            return Err(range("solver.tolerance", s.tolerance, "tolerance > 0 (J)"));
        }
        if !(s.energy_tolerance > 0.0 && s.energy_tolerance <= 1e-3) {
            return Err(range(
                "solver.energy_tolerance",
                s.energy_tolerance,
                "0 < energy_tolerance <= 1e-3 (relative energy error per step)",
            ));
        }
        if !(1..=1000).contains(&s.max_iterations) {
            return Err(Error::Config(format!(
                "solver.max_iterations = {}: allowed range 1 to 1000",
                s.max_iterations
            )));
        }
        if let Cutbacks::Count(n) = s.max_cutbacks {
            if n > Cutbacks::MAX {
                return Err(Error::Config(Cutbacks::refusal(n)));
            }
        }
        Ok(())
    }
}

/// Time profile of the actuator torque.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TorqueProfile {
    /// No torque.
    None,
    /// `M = amplitude` for all times.
    Constant,
    /// `M = amplitude` from `start` on, 0 before.
    Step,
    /// Linear rise from 0 at `start` to `amplitude` at `start + duration`, constant after.
    Ramp,
    /// `M = amplitude sin(2π frequency (t − start) + phase)` from `start` on.
    Sine,
    /// Linear interpolation in a CSV table `time_s,torque_Nm`.
    Table,
}

/// Actuator torque at the pivot: the one description of the torque profile, which the torque
/// term ([`crate::terms::Torque`]) keeps and evaluates ([`crate::terms::Torque::value`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Torque {
    /// Time profile.
    pub profile: TorqueProfile,
    /// Amplitude \[N·m\], counter-clockwise positive.
    pub amplitude: f64,
    /// Start time \[s\].
    pub start: f64,
    /// Rise time of the ramp \[s\].
    pub duration: f64,
    /// Frequency of the sine \[Hz\].
    pub frequency: f64,
    /// Phase of the sine \[rad\].
    pub phase: f64,
    /// CSV table for `profile = "table"`.
    pub file: Option<PathBuf>,
    /// `true`: the load turns with the body (pure torque at every angle); `false`: fixed direction.
    pub follower: bool,
}

impl Default for Torque {
    fn default() -> Self {
        Self {
            profile: TorqueProfile::None,
            amplitude: 0.0,
            start: 0.0,
            duration: 0.0,
            frequency: 0.0,
            phase: 0.0,
            file: None,
            follower: true,
        }
    }
}

impl Torque {
    /// The `[torque]` rules: the keys each profile needs.
    fn validate(&self) -> Result<(), Error> {
        let t = self;
        finite("torque.amplitude", t.amplitude)?;
        non_negative("torque.start", t.start, "s")?;
        non_negative("torque.duration", t.duration, "s")?;
        non_negative("torque.frequency", t.frequency, "Hz")?;
        finite("torque.phase", t.phase)?;
        if t.profile == TorqueProfile::Ramp && t.duration <= 0.0 {
            return Err(range(
                "torque.duration",
                t.duration,
                "duration > 0 s for profile = \"ramp\"",
            ));
        }
        if t.profile == TorqueProfile::Sine && t.frequency <= 0.0 {
            return Err(range(
                "torque.frequency",
                t.frequency,
                "frequency > 0 Hz for profile = \"sine\"",
            ));
        }
        if t.profile == TorqueProfile::Table && t.file.is_none() {
            return Err(Error::Config(
                "torque.file: required for profile = \"table\" (a CSV time_s,torque_Nm)".into(),
            ));
        }
        Ok(())
    }
}

/// What the wall is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WallKind {
    /// No wall (the basics tutorial).
    None,
    /// A rigid obstacle, the half-plane `x <= wall.x` (no mesh).
    Rigid,
    /// The contact tutorial's steel block, meshed as a second body, fixed on its left, top and
    /// bottom edges; its right edge (`x = wall.x`) is the contact face.
    Deformable,
}

/// The wall (see [`WallKind`]); the block's keys apply to `kind = "deformable"`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Wall {
    /// Rigid or deformable, or none.
    pub kind: WallKind,
    /// `x` of the contact face \[m\] (the hanging head's leftmost point is at −0.06 m).
    pub x: f64,
    /// Width of the block, to the left of the face \[m\].
    pub width: f64,
    /// Height of the block \[m\].
    pub height: f64,
    /// `y` of the block's centre \[m\].
    pub center_y: f64,
    /// Young's modulus of the block \[Pa\].
    pub youngs_modulus: f64,
    /// Poisson's ratio of the block \[-\].
    pub poisson_ratio: f64,
    /// Density of the block \[kg/m³\].
    pub density: f64,
    /// Thickness of the block \[m\].
    pub thickness: f64,
    /// Element size in the block \[m\] (the tutorial's `r_head/5`).
    pub mesh_size: f64,
    /// Element size along the contact face \[m\] (the tutorial's `r_head/20`).
    pub face_size: f64,
}

impl Default for Wall {
    fn default() -> Self {
        Self {
            kind: WallKind::None,
            x: -0.06,
            width: 0.025,
            height: 0.25,
            center_y: -0.24,
            youngs_modulus: 2.1e11,
            poisson_ratio: 0.3,
            density: 7800.0,
            thickness: 0.01,
            mesh_size: 0.012,
            face_size: 0.003,
        }
    }
}

impl Wall {
    /// The `[wall]` rules (the wall's overlap with the pendulum at its release angle is checked
    /// with the mesh, by the model).
    fn validate(&self) -> Result<(), Error> {
        let w = self;
        finite("wall.x", w.x)?;
        finite("wall.center_y", w.center_y)?;
        if w.kind == WallKind::Deformable {
            positive("wall.width", w.width, "m")?;
            positive("wall.height", w.height, "m")?;
            positive("wall.youngs_modulus", w.youngs_modulus, "Pa")?;
            if !(w.poisson_ratio > 0.0 && w.poisson_ratio < 0.5) {
                return Err(range("wall.poisson_ratio", w.poisson_ratio, "0 < poisson_ratio < 0.5"));
            }
            positive("wall.density", w.density, "kg/m^3")?;
            positive("wall.thickness", w.thickness, "m")?;
            positive("wall.mesh_size", w.mesh_size, "m")?;
            positive("wall.face_size", w.face_size, "m")?;
            for (key, size) in [("wall.mesh_size", w.mesh_size), ("wall.face_size", w.face_size)] {
                if size > w.width.max(w.height) || size < 1e-5 * w.height {
                    return Err(range(
                        key,
                        size,
                        &format!(
                            "1e-5 x wall.height <= size <= the block's size ({} m)",
                            w.width.max(w.height)
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// How the contact force is evaluated over a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContactMethod {
    /// The secant (discrete gradient) of the contact energy over the step, with the impact located
    /// and resolved in sub-steps: the work of the contact force equals the change of contact energy.
    EnergyConsistent,
    /// The tutorial's: the penalty force at the end of the step, no impact location. It gains
    /// energy at impacts; kept to show the difference.
    Penalty,
}

/// Contact between the head's arc and the wall face.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Contact {
    /// How the force is evaluated over a step.
    pub method: ContactMethod,
    /// Normal pressure per unit penetration \[N/m³\]: energy `½ k g²` per unit reference contact
    /// area. The default 2e10 is the tutorial's `kₙ = 1e10`: its energy density `kₙ g²` has no ½.
    pub stiffness: f64,
    /// Gauss points per edge of the head's arc.
    pub points_per_edge: usize,
    /// Sub-steps per contact time scale `δ_max / v` while the head is in contact (see
    /// [`crate::simulation`]'s impact resolution). The default 10 meets the converged references
    /// (rebound within 4e-4°, penetration within 0.3 %, the stiff contact's rebound within 0.03°)
    /// at 2.7 times the cost of the same run without a wall; 20 changes them by less than 1e-4°.
    pub substeps: usize,
}

impl Default for Contact {
    fn default() -> Self {
        Self {
            method: ContactMethod::EnergyConsistent,
            stiffness: 2e10,
            points_per_edge: 8,
            substeps: 10,
        }
    }
}

impl Contact {
    /// The `[contact]` rules; the energy-consistent method with a wall needs the energy-momentum
    /// `scheme`.
    fn validate(&self, w: &Wall, scheme: Scheme) -> Result<(), Error> {
        let c = self;
        positive("contact.stiffness", c.stiffness, "N/m^3")?;
        if !(1..=64).contains(&c.points_per_edge) {
            return Err(Error::Config(format!(
                "contact.points_per_edge = {}: allowed range 1 to 64",
                c.points_per_edge
            )));
        }
        if !(4..=1000).contains(&c.substeps) {
            return Err(Error::Config(format!(
                "contact.substeps = {}: allowed range 4 to 1000",
                c.substeps
            )));
        }
        if w.kind != WallKind::None && c.method == ContactMethod::EnergyConsistent && scheme != Scheme::EnergyMomentum {
            return Err(Error::Config(format!(
                "contact.method = \"energy-consistent\" needs time.scheme = \"energy-momentum\" (this run has \"{}\"); \
                 the Newmark schemes evaluate the contact force at the end of the step: set contact.method = \"penalty\"",
                scheme.name()
            )));
        }
        Ok(())
    }
}

/// What a run writes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Output {
    /// Output folder; each run gets a fresh subfolder unless `--out` names one.
    pub dir: PathBuf,
    /// Offer every n-th step to the animations and the viewer (the last step is always offered);
    /// also the ParaView thinning unless `paraview_every` is set.
    pub every: usize,
    /// Write every n-th step as a ParaView frame (the last step is always written); `None`: as
    /// `every`.
    pub paraview_every: Option<usize>,
    /// Magnification of the elastic part of the displacement in pictures; `None`: automatic.
    pub magnification: Option<f64>,
    /// Write `theta.png` and `energy.png`.
    pub plots: bool,
    /// Write `displacement.gif` and `von_mises.gif`.
    pub animation: bool,
    /// Write `pendulum.pvd` and `frames/step_NNNNN.vtu`.
    pub paraview: bool,
    /// Write `viewer.html`.
    pub viewer: bool,
    /// Upper bound on frames in the animations and the viewer (frames are thinned to fit).
    pub max_frames: usize,
    /// The run stops with an error when the energy error (energy change minus the work of the
    /// torque, over the energy scale) exceeds this fraction; 0 switches the watchdog off.
    pub energy_watchdog: f64,
}

impl Output {
    /// The ParaView thinning: `paraview_every`, or `every` when that is not set.
    pub fn paraview_stride(&self) -> usize {
        self.paraview_every.unwrap_or(self.every).max(1)
    }

    /// The `[output]` rules.
    fn validate(&self) -> Result<(), Error> {
        let o = self;
        if o.every == 0 {
            return Err(Error::Config("output.every = 0: allowed range 1 and up".into()));
        }
        if o.paraview_every == Some(0) {
            return Err(Error::Config(
                "output.paraview_every = 0: allowed range 1 and up (output.paraview = false writes no frames)".into(),
            ));
        }
        non_negative(
            "output.energy_watchdog",
            o.energy_watchdog,
            "(a fraction of the energy scale; 0: off)",
        )?;
        if let Some(mag) = o.magnification {
            if !(mag >= 0.0 && mag.is_finite()) {
                return Err(range(
                    "output.magnification",
                    mag,
                    "magnification >= 0 (omit the key for automatic)",
                ));
            }
        }
        if o.max_frames < 2 {
            return Err(Error::Config(format!(
                "output.max_frames = {}: allowed range 2 and up",
                o.max_frames
            )));
        }
        Ok(())
    }
}

impl Default for Output {
    fn default() -> Self {
        Self {
            dir: PathBuf::from("results"),
            every: 1,
            paraview_every: None,
            magnification: None,
            plots: true,
            animation: true,
            paraview: true,
            viewer: true,
            max_frames: 200,
            energy_watchdog: 0.01,
        }
    }
}

impl Config {
    /// Reads a configuration file (or the defaults when `path` is `None`) and applies
    /// `key=value` overrides, then validates.
    pub fn load(path: Option<&Path>, overrides: &[String]) -> Result<Self, Error> {
        let mut text = None;
        let mut doc = match path {
            Some(p) => {
                let read = std::fs::read_to_string(p)
                    .map_err(|e| Error::Config(format!("cannot read config file {}: {e}", p.display())))?;
                let doc = read
                    .parse::<toml::Table>()
                    .map_err(|e| Error::Config(format!("config file {}: {e}", p.display())))?;
                text = Some(read);
                doc
            }
            None => toml::Table::new(),
        };
        if let Some(folder) = path.and_then(Path::parent) {
            resolve_relative_paths(&mut doc, folder);
        }
        for o in overrides {
            apply_override(&mut doc, o)?;
        }
        let source = path.map(|p| p.display().to_string()).unwrap_or_else(|| "--set".into());
        let cfg: Config = Config::deserialize(toml::Value::Table(doc)).map_err(|e| {
            let message = e.to_string();
            let located = unknown_key_message(message.trim(), text.as_deref(), overrides);
            Error::Config(format!(
                "{source}: {}",
                located.unwrap_or_else(|| message.trim().to_string())
            ))
        })?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Parses TOML text (no overrides) and validates.
    pub fn from_toml_str(text: &str) -> Result<Self, Error> {
        let doc = text
            .parse::<toml::Table>()
            .map_err(|e| Error::Config(e.to_string().trim().to_string()))?;
        let cfg: Config = Config::deserialize(toml::Value::Table(doc)).map_err(|e| {
            let message = e.to_string();
            let located = unknown_key_message(message.trim(), Some(text), &[]);
            Error::Config(located.unwrap_or_else(|| message.trim().to_string()))
        })?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Checks every value against its allowed range, section by section (each section's rules
    /// are its `validate` method, next to its struct); the message names the key.
    pub fn validate(&self) -> Result<(), Error> {
        self.geometry.validate()?;
        self.mesh.validate(&self.geometry)?;
        self.material.validate()?;
        self.gravity.validate()?;
        self.initial.validate()?;
        self.time.validate()?;
        self.solver.validate()?;
        self.torque.validate()?;
        self.wall.validate()?;
        self.contact.validate(&self.wall, self.time.scheme)?;
        self.output.validate()
    }
}

fn range(key: &str, value: f64, allowed: &str) -> Error {
    Error::Config(format!("{key} = {value}: allowed {allowed}"))
}

fn finite(key: &str, v: f64) -> Result<(), Error> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(range(key, v, "a finite number"))
    }
}

fn positive(key: &str, v: f64, unit: &str) -> Result<(), Error> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(range(key, v, &format!("a finite value > 0 {unit}")))
    }
}

fn non_negative(key: &str, v: f64, unit: &str) -> Result<(), Error> {
    if v >= 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(range(key, v, &format!("a finite value >= 0 {unit}")))
    }
}

fn within(key: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), Error> {
    if v >= lo && v <= hi {
        Ok(())
    } else {
        Err(range(key, v, &format!("{lo} to {hi} {unit}")))
    }
}

/// For serde's "unknown field" error (`message`: ``unknown field `edn`, expected one of `dt`,
/// `end`, …`` and, in a section, ``in `time` ``), a message that names the key, its section, where
/// it was written (the line in the configuration file `text`, or the `--set` override) and the
/// allowed key nearest to it:
/// `unknown key "edn" in [time] at line 3; did you mean "end"? (allowed: dt, end, …)`.
/// `None` for any other error.
fn unknown_key_message(message: &str, text: Option<&str>, overrides: &[String]) -> Option<String> {
    let rest = message.strip_prefix("unknown field `")?;
    let (key, rest) = rest.split_once('`')?;
    let (expected, section) = match rest.rsplit_once("\nin `") {
        Some((expected, section)) => (expected, Some(section.trim_end_matches('`'))),
        None => (rest, None),
    };
    // the allowed keys: every `quoted` word after "expected" (`a`; `a` or `b`; one of `a`, `b`, …)
    let allowed: Vec<&str> = expected.split('`').skip(1).step_by(2).collect();
    let full = section.map_or(key.to_string(), |s| format!("{s}.{key}"));
    let place = if let Some(o) = overrides
        .iter()
        .find(|o| o.split('=').next().map(str::trim) == Some(&full))
    {
        format!(" in --set {o}")
    } else if let Some(line) = text.and_then(|t| line_of_unknown_key(t, key)) {
        format!(" at line {line}")
    } else {
        String::new()
    };
    let within = section.map_or(" at the top level".to_string(), |s| format!(" in [{s}]"));
    let nearest = allowed
        .iter()
        .map(|a| (edit_distance(key, a), *a))
        .min()
        .filter(|(d, a)| *d <= 2.max(a.chars().count() / 3))
        .map_or(String::new(), |(_, a)| format!("; did you mean \"{a}\"?"));
    Some(format!(
        "unknown key \"{key}\"{within}{place}{nearest} (allowed: {})",
        allowed.join(", ")
    ))
}

/// Whether `message` (the text of an [`Error::Config`]) reports an unknown key, as
/// [`Config::load`] words it; for callers that treat a misspelled key apart from a bad value.
pub fn reports_an_unknown_key(message: &str) -> bool {
    message.contains("unknown key \"")
}

/// The line (1-based) of the unknown `key` in the configuration file `text`: toml's own reading of
/// the file as a [`Config`] points at it (when that is its first error).
fn line_of_unknown_key(text: &str, key: &str) -> Option<usize> {
    let e = toml::from_str::<Config>(text).err()?;
    let span = e.span()?;
    e.message()
        .starts_with(&format!("unknown field `{key}`"))
        .then(|| text[..span.start].matches('\n').count() + 1)
}

/// The optimal-string-alignment distance of `a` and `b`: insertions, deletions, substitutions and
/// swaps of two neighbours (`edn` → `end`: 1) each count 1.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for i in 0..=a.len() {
        d[i][0] = i;
    }
    for j in 0..=b.len() {
        d[0][j] = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            d[i][j] = (d[i - 1][j] + 1).min(d[i][j - 1] + 1).min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d[i][j] = d[i][j].min(d[i - 2][j - 2] + 1);
            }
        }
    }
    d[a.len()][b.len()]
}

/// Keys naming input files; in a configuration file, a relative one is relative to the file's
/// folder. (`output.dir` is not an input: like `--out`, it is relative to where the run starts.)
pub const PATH_KEYS: [(&str, &str); 2] = [("torque", "file"), ("mesh", "file")];

/// Makes the relative paths of [`PATH_KEYS`] in a configuration file's document relative to the
/// file's folder (`folder`); absolute paths and values that are not strings are left alone (the
/// latter fail with their key when deserialised).
fn resolve_relative_paths(doc: &mut toml::Table, folder: &Path) {
    for (section, key) in PATH_KEYS {
        let value = doc
            .get_mut(section)
            .and_then(toml::Value::as_table_mut)
            .and_then(|t| t.get_mut(key));
        if let Some(toml::Value::String(p)) = value {
            if Path::new(p.as_str()).is_relative() {
                *p = folder.join(p.as_str()).to_string_lossy().into_owned();
            }
        }
    }
}

/// Applies one `section.key=value` override to a TOML document. The value is read as TOML
/// (numbers, booleans, quoted strings); a bare word that is not valid TOML is taken as a string.
fn apply_override(doc: &mut toml::Table, assignment: &str) -> Result<(), Error> {
    let (key, value) = assignment.split_once('=').ok_or_else(|| {
        Error::Config(format!(
            "--set {assignment}: expected key=value, e.g. mesh.max_size=0.01"
        ))
    })?;
    let key = key.trim();
    let value = value.trim();
    let parsed: toml::Value = match format!("v = {value}").parse::<toml::Table>() {
        Ok(mut t) => t.remove("v").expect("parsed key"),
        Err(_) => toml::Value::String(value.to_string()),
    };
    let parts: Vec<&str> = key.split('.').collect();
    if parts.len() < 2 || parts.iter().any(|p| p.is_empty()) {
        return Err(Error::Config(format!(
            "--set {assignment}: the key must be section.name (any depth: a.b.c), e.g. mesh.max_size or time.dt"
        )));
    }
    // walk (and create) the tables of every part but the last, at any depth
    let (last, tables) = parts.split_last().expect("two parts at least");
    let mut table = doc;
    for (depth, part) in tables.iter().enumerate() {
        let entry = table
            .entry(part.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        table = entry.as_table_mut().ok_or_else(|| {
            Error::Config(format!(
                "--set {assignment}: `{}` is a value, not a section",
                parts[..=depth].join(".")
            ))
        })?;
    }
    table.insert(last.to_string(), parsed);
    Ok(())
}

/// A commented configuration listing every key with its default and unit.
pub fn commented_default() -> String {
    include_str!("default_config.toml").to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_misspelled_key_names_its_section_line_and_nearest_allowed_key() {
        let dir = std::env::temp_dir().join(format!("pendulum-config-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("bad.toml");
        for (text, says) in [
            (
                "[time]\ndt = 0.01\nedn = 2.0\n",
                "unknown key \"edn\" in [time] at line 3; did you mean \"end\"? (allowed: dt, end,",
            ),
            (
                "# a comment\n\n[tme]\ndt = 0.01\n",
                "unknown key \"tme\" at the top level at line 3; did you mean \"time\"?",
            ),
            (
                "[mesh]\nmax_sise = 0.01\n",
                "unknown key \"max_sise\" in [mesh] at line 2; did you mean \"max_size\"?",
            ),
            (
                "[wall]\nkind = \"rigid\"\n[contact]\nstifness = 1e10\n",
                "unknown key \"stifness\" in [contact] at line 4; did you mean \"stiffness\"?",
            ),
        ] {
            std::fs::write(&file, text).unwrap();
            let e = Config::load(Some(&file), &[]).unwrap_err().to_string();
            assert!(e.contains(says), "{text:?}:\n{e}\nshould contain\n{says}");
            let e = Config::from_toml_str(text).unwrap_err().to_string();
            assert!(e.contains(says), "from_toml_str({text:?}):\n{e}");
        }
        // nothing near: no guess, but the allowed keys
        std::fs::write(&file, "[time]\nwhatever = 1\n").unwrap();
        let e = Config::load(Some(&file), &[]).unwrap_err().to_string();
        assert!(
            e.contains("unknown key \"whatever\" in [time] at line 2 (allowed: dt, end"),
            "{e}"
        );
        assert!(!e.contains("did you mean"), "{e}");
        // from --set: the override is named instead of a line
        std::fs::write(&file, "[time]\ndt = 0.01\n").unwrap();
        let e = Config::load(Some(&file), &["time.edn=2".into()])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("unknown key \"edn\" in [time] in --set time.edn=2; did you mean \"end\"?"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn edit_distance_counts_a_swap_of_neighbours_as_one() {
        for (a, b, d) in [
            ("edn", "end", 1),
            ("end", "end", 0),
            ("max_sise", "max_size", 1),
            ("tme", "time", 1),
            ("", "dt", 2),
            ("kitten", "sitting", 3),
        ] {
            assert_eq!(edit_distance(a, b), d, "{a} → {b}");
        }
    }

    #[test]
    fn commented_default_parses_to_the_defaults() {
        let cfg = Config::from_toml_str(&commented_default()).expect("the shipped default config is valid");
        assert_eq!(cfg, Config::default());
    }

    #[test]
    fn relative_paths_in_a_file_are_relative_to_its_folder_and_overrides_to_the_current_one() {
        let dir = std::env::temp_dir().join(format!("pendulum-fem-config-paths-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("p.toml");
        std::fs::write(
            &file,
            "[torque]\nprofile = \"table\"\nfile = \"t.csv\"\n[mesh]\nfile = \"m.msh\"\n[output]\ndir = \"out\"\n",
        )
        .unwrap();
        let cfg = Config::load(Some(&file), &[]).unwrap();
        assert_eq!(cfg.torque.file.as_deref(), Some(dir.join("t.csv").as_path()));
        assert_eq!(cfg.mesh.file.as_deref(), Some(dir.join("m.msh").as_path()));
        assert_eq!(
            cfg.output.dir,
            Path::new("out"),
            "an output folder is relative to the current folder"
        );
        let cfg = Config::load(Some(&file), &["torque.file=u.csv".into()]).unwrap();
        assert_eq!(cfg.torque.file.as_deref(), Some(Path::new("u.csv")), "--set: as typed");
        let absolute = dir.join("abs.csv");
        std::fs::write(&file, format!("[torque]\nprofile = \"table\"\nfile = {:?}\n", absolute)).unwrap();
        let cfg = Config::load(Some(&file), &[]).unwrap();
        assert_eq!(cfg.torque.file.as_deref(), Some(absolute.as_path()));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn refine_divides_every_mesh_size() {
        let base = Config::default().mesh_sizes();
        let cfg = Config::load(None, &["mesh.refine=2".into(), "mesh.rod_size=0.006".into()]).unwrap();
        let s = cfg.mesh_sizes();
        for (a, b) in [
            (s.max_size, base.max_size),
            (s.head, base.head),
            (s.hinge_edge, base.hinge_edge),
            (s.hinge_corner, base.hinge_corner),
            (s.circle_edge, base.circle_edge),
            (s.rod, 0.006),
        ] {
            assert_eq!(a, b / 2.0);
        }
        let err = Config::load(None, &["mesh.refine=0".into()]).unwrap_err().to_string();
        assert!(err.contains("mesh.refine") && err.contains("0.1 to 100"), "{err}");
    }

    #[test]
    fn overrides_are_typed_and_checked() {
        let cfg = Config::load(None, &["mesh.max_size=0.01".into(), "material.plane=strain".into()]).unwrap();
        assert_eq!(cfg.mesh.max_size, 0.01);
        assert_eq!(cfg.material.plane, Plane::Strain);
        let err = Config::load(None, &["mesh.max_size=-1".into()])
            .unwrap_err()
            .to_string();
        assert!(err.contains("mesh.max_size"), "{err}");
        // keys of any depth reach nested tables; one that runs through a value says which
        let mut doc = toml::Table::new();
        apply_override(&mut doc, "a.b.c=3").unwrap();
        assert_eq!(doc["a"]["b"]["c"].as_integer(), Some(3));
        let err = apply_override(&mut doc, "a.b.c.d=1").unwrap_err().to_string();
        assert!(err.contains("`a.b.c` is a value"), "{err}");
        let err = Config::load(None, &["time.dt.x=1".into()]).unwrap_err().to_string();
        assert!(err.contains("time.dt"), "{err}");
    }

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
