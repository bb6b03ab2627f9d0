//! Orchestration: builds the model from a configuration and a mesh, sets the initial state, and
//! advances it step by step with cut-backs.
//!
//! **Initial state** (pivot at the origin, `R = R(θ₀)`): `u₀ = (R − I) X`, `v₀ = ω₀ e_z × x`,
//! `x = R X`. The initial acceleration is either zero (the tutorial's start) or the rigid-body value
//! `a₀ = α₀ e_z × x − ω₀² x`, with `α₀ = (τ_g + M(0)) / I_pivot` from the torque balance about the
//! pivot: `τ_g = −ρ t g ∫ x_x dA` is the moment of gravity and `I_pivot = ρ t ∫ |X|² dA`.
//!
//! With the rigid start the body is also put into elastic equilibrium with gravity, the torque
//! and the d'Alembert forces of that rigid motion: `u₀` minimises
//! `Π_el(u) + Π_g(u) + Π_torque(u, 0) + (M a₀)·u` under the hinge, starting from the rigid rotation.
//! The rotation about the pivot is a zero-energy mode of that static problem (its moment balance
//! is what fixes `α₀`), so a mass term `½ (u − u_rigid)ᵀ M (u − u_rigid) / (0.01 s)²` pins it (the
//! conditioning of an ordinary step);
//! its residual force is removed by re-centring it on the solution and solving again (proximal
//! point iterations, a few passes). Starting
//! undeformed instead excites axial vibrations that the trapezoidal rule never damps (the hinge
//! force then oscillates by 5e-5 of the weight for a pendulum at rest). The `"zero"` start is
//! the tutorial's: undeformed, at rest in its own frame (`initial.elastic = "undeformed"` also gives
//! an undeformed rigid start, for comparisons with codes that start that way).
//!
//! **Steps**: each user step `tₙ → tₙ + Δt` solves the energy-momentum system
//! ([`crate::energy_momentum`], the default) or minimises the Newmark incremental potential
//! ([`crate::newmark`]; `"trapezoidal"`, `"hht"`) with Newton ([`crate::newton`]). If Newton fails,
//! the step is split into two halves, recursively, as `solver.max_cutbacks` allows (by default
//! down to the mesh's wave time, [`crate::config::Cutbacks`]); then the run stops with an error
//! naming the step, the time and the last residual ([`Error::TimeStep`]).
//!
//! **Stepping interface** (`stepper`): [`Simulation::step`] with any `dt`, rollback of a failed
//! step, the held torque input, outputs on request; snapshots of the complete state
//! ([`Snapshot`], `snapshot`).
//!
//! **Files**: `model` (the [`Model`]), `record` (the output records [`StepRecord`], [`Frame`]),
//! `init` (the set-up and the initial state), `measures` (outputs and rigid-body measures of the
//! current state), `schemes` (one step of each time scheme), `substep` (an output step in
//! sub-steps and cut-backs), `clock`, `stepper` (`step`, `advance` and the outputs on request), `impact`,
//! `snapshot`, `body`, `split`, `shared` (the operators models of one mesh share).

use crate::linsolve::Cholesky;
use crate::newmark::State;
use crate::newton::Solver;
use crate::rigid::Unwrap;
#[cfg(doc)]
use crate::Error;

pub mod body;
mod clock;
mod impact;
mod init;
mod measures;
mod model;
mod pool;
mod record;
mod reduced;
mod schemes;
pub mod shared;
pub(crate) mod snapshot;
pub mod split;
mod stepper;
mod substep;

pub use body::{Body, BodySpec};
pub use impact::{ContactEvent, ContactEventKind};
pub use init::Built;
pub use model::{Model, CONTACT_BOUNDARY, HINGE_BOUNDARY};
pub use record::{ContactRecord, Frame, FrameData, StepRecord};
pub use shared::forget_shared;
pub use snapshot::{fingerprint, Fingerprint, Snapshot, SNAPSHOT_VERSION};
pub use stepper::Energies;

use clock::Clock;
use measures::Kinematics;

/// Relative equilibrium tolerance of a converged step: `‖∇Φ + Cᵀλ‖∞ ≤ 10⁻⁴ × load scale`, where the
/// load scale is the largest nodal gravity or inertia force. Together with the energy-norm criterion
/// (`solver.tolerance`) it guards against a small update that hides an unbalanced state.
pub const RESIDUAL_TOLERANCE: f64 = 1e-4;

/// A running simulation.
pub struct Simulation {
    /// The model.
    pub model: Model,
    /// Newton workspace (factorisation, buffers).
    pub solver: Solver,
    /// Current state. For a reduced body without a wall, its displacement and velocity are brought
    /// up to date only when read through [`Simulation::displacement`], [`Simulation::velocity`]
    /// or a frame: read them there.
    pub state: State,
    /// Current hinge multipliers \[N\].
    pub lambda: [f64; 2],
    /// Steps done.
    pub step: usize,
    /// Newton iterations (linear solves) so far.
    pub total_iterations: usize,
    /// Numeric factorisations so far.
    pub total_factorizations: usize,
    /// Cut-backs so far.
    pub cutbacks: usize,
    /// Work of the external loads of the extra terms (the torque) since the start \[J\].
    pub torque_work: f64,
    unwrap: Unwrap,
    /// Proxy angle of the current state, unwrapped \[rad\].
    theta: f64,
    /// The time of the state as `base + count · dt` over a run of equal steps.
    clock: Clock,
    /// Newton iterations of the last step (0 before the first).
    last_iterations: usize,
    /// The torque value held by [`Simulation::set_torque`] \[N m\], if any.
    held_torque: Option<f64>,
    /// Nodal stress evaluations so far ([`Simulation::stress_evaluations`]).
    stress_evaluations: usize,
    /// Impacts so far.
    impacts: usize,
    /// Contact events so far (append-only within a run: roll-backs truncate it).
    events: Vec<ContactEvent>,
    /// Contact events copied by snapshots and restores ([`Simulation::events_copied`]).
    events_copied: std::sync::atomic::AtomicUsize,
    /// The impact in progress.
    contact_phase: Option<impact::ContactPhase>,
    /// Whether the sub-steps inside impacts are recorded ([`Simulation::record_impacts`]).
    recording_impacts: bool,
    /// The records of the sub-steps inside impacts not yet taken
    /// ([`Simulation::take_impact_records`]; roll-backs truncate it).
    impact_records: Vec<StepRecord>,
    /// The sub-step ends of the impact in progress, for the predictor of a chattering contact.
    impact_trail: impact::ImpactTrail,
    /// The reduced body's coordinates and momenta (`model.kind = "reduced"`), from which
    /// [`Simulation::state`] is reconstructed after every step.
    reduced: Option<crate::reduced::ReducedState>,
    /// The reduced body's error estimate so far ([`crate::reduced::validity`]).
    validity: crate::reduced::Validity,
    /// The reduced body's last fully evaluated stress state, for [`Simulation::von_mises_max`].
    stress_reference: crate::reduced::outputs::StressReference,
    /// A warning not yet taken by [`Simulation::take_warning`].
    pending_warning: Option<String>,
    /// Whether [`Simulation::state`]'s displacement and velocity lag the reduced body's
    /// coordinates (a reduced body without a wall reconstructs its fields only when they are read).
    fields_stale: bool,
    /// The reduced body's fields `[u, v]`, reconstructed on the first read after a step.
    lazy_fields: std::sync::OnceLock<[Vec<f64>; 2]>,
    /// `(t, α)` at the start of the previous (sub)step, for the predictor's `α̇`.
    previous_alpha: Option<(f64, f64)>,
    /// Rigid-body measures of the current state, once computed.
    rates: Option<Kinematics>,
    /// `M x` of the current positions (valid with `rates`).
    mx: Vec<f64>,
    /// The elastic terms' start data of a state (one per body) with the displacement it was made
    /// from ([`Simulation::elastic_starts`]).
    starts: Option<(Vec<f64>, Vec<Vec<f64>>)>,
    /// For [`Simulation::acceleration_field`]: the mass matrix factorised, the hinge rows and
    /// `M⁻¹Cᵀ`, made on first use.
    mass_solver: Option<(Cholesky, [Vec<f64>; 2], Vec<f64>)>,
}
