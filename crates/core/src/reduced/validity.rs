//! Whether the reduced body applies: an estimate of its error from the full model, evaluated as
//! it runs, and one warning when the estimate passes a bound.
//!
//! The reduced body replaces the full model's hyperelastic strain energy `W(u)` in the frame by
//! its quadratic part `½ qᵀΛq` on the modes. What it leaves out is measured by the full model's
//! elastic forces at the reconstructed displacement `u = Φ q` against the reduced ones:
//!
//! ```text
//! r = Φᵀ ∇W(Φ q) − Λ q,      η = ‖r‖_{Λ⁻¹} / ‖q‖_Λ = √(Σ r_k²/λ_k) / √(Σ λ_k q_k²)
//! ```
//!
//! `η` is the relative error of the reduced elastic forces in the energy norm (dimensionless). It
//! grows with the strains (the Green strain's quadratic part against its linear part) and with the
//! stress stiffening that linear modes lack: a soft rod hanging in tension under its head's weight
//! is stiffer in bending than its modes say, by the ratio of the tension's geometric stiffness to
//! the bending stiffness, which is what `r` projects onto the bending modes.
//!
//! Measured over a 3 s swing from 45° at dt = 0.01 s (tutorial mesh; ν = 0.45, ρ = 1000 kg/m³ for
//! the soft ones), the largest `η` and the largest difference of θ from the full model's:
//!
//! | E | `η` | θ off by |
//! |---|---|---|
//! | steel (210 GPa, ν = 0.3, ρ = 7800) | 8.7e-6 | (2e-6 rad at 20°, dt = 1 ms) |
//! | 10 MPa | 0.026 | 0.080° |
//! | 3 MPa | 0.10 | 0.048° |
//! | 1 MPa | 0.49 | 0.21° |
//! | 0.1 MPa | 76 | 15.6° |
//!
//! θ's error is not monotonic in `η` (it oscillates with the swing), but every case whose θ is
//! off by more than 0.1° has `η` above 0.1. [`WARNING_BOUND`] is 1 %, ten times lower, and a
//! thousand times above steel's.

use super::ReducedBody;
use crate::model::Model;
use crate::terms::{StepContext, Term};

/// The estimate `η` above which the reduced body warns (see the module doc).
pub const WARNING_BOUND: f64 = 0.01;

/// The estimate is evaluated at the start, whenever the strain energy passes the largest at which
/// it was evaluated by this factor, and at least every [`EVERY`] steps: one evaluation assembles the
/// full model's elastic forces (tens of reduced steps' work), and `η` grows with the strains.
pub const STRAIN_FACTOR: f64 = 1.1;

/// The most steps between two evaluations of the estimate.
pub const EVERY: usize = 100;

/// The running estimate of a reduced run and its warning.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Validity {
    /// The largest `η` so far and the time it was reached \[s\].
    pub largest: Option<(f64, f64)>,
    /// The warning, once `η` has passed [`WARNING_BOUND`].
    pub warning: Option<String>,
    /// Steps since the last evaluation.
    pub steps: usize,
    /// The largest strain energy at which the estimate was evaluated \[J\].
    pub strain: f64,
    /// The contact events seen by the deformable wall's check ([`crate::reduced::wall`]).
    pub events: usize,
}

impl Validity {
    /// Counts a step whose state has the strain energy `strain` \[J\]; whether the estimate is due
    /// (see [`STRAIN_FACTOR`]).
    pub fn due(&mut self, strain: f64) -> bool {
        self.steps += 1;
        self.steps >= EVERY || strain > STRAIN_FACTOR * self.strain
    }

    /// Keeps `message` as the run's warning unless one was given before; returns it if kept.
    pub fn warn(&mut self, message: String) -> Option<&str> {
        if self.warning.is_some() {
            return None;
        }
        self.warning = Some(message);
        self.warning.as_deref()
    }

    /// Takes the estimate `eta` of the state at time `t` with the strain energy `strain` \[J\];
    /// returns the warning if this estimate is the first to pass the bound.
    pub fn observe(&mut self, eta: f64, t: f64, strain: f64) -> Option<&str> {
        self.steps = 0;
        self.strain = self.strain.max(strain);
        if self.largest.is_none_or(|(worst, _)| eta > worst) {
            self.largest = Some((eta, t));
        }
        if self.warning.is_none() && eta > WARNING_BOUND {
            self.warning = Some(format!(
                "warning: the reduced body (model.kind = \"reduced\") does not apply here: at t = {t:.6} s its elastic \
                 forces differ from the full model's by {:.1} % (estimate η = {eta:.3e}, bound {WARNING_BOUND:.0e}): its \
                 linear modes miss this body's strains or stress stiffening, and θ, the stresses and the forces may \
                 be off by more than the bounds verified for steel (E = 1 MPa at 45°: η = 0.49, θ 0.2° off over \
                 3 s); use model.kind = \"full\"",
                100.0 * eta
            ));
            return self.warning.as_deref();
        }
        None
    }
}

impl ReducedBody {
    /// The estimate `η` of the module doc at the amplitudes `q`, with the full model `model` (whose
    /// pendulum this body reduces).
    pub fn error_estimate(&self, model: &Model, q: &[f64]) -> f64 {
        let nd = self.reference.len();
        let mut u = vec![0.0; model.pattern.n];
        self.modal_sum(q, &mut u[..nd]);
        let cx = StepContext::at(&u, 0.0, 0.0, None);
        let mut force = vec![0.0; model.pattern.n];
        model.bodies[0].elastic.add_gradient(&u, &cx, &mut force);
        relative_error(&self.shapes, &self.stiffness, q, &force[..nd])
    }
}

/// `η = √(Σ ρ_k²/λ_k) / √(Σ λ_k a_k²)`, `ρ_k = φ_k · f − λ_k a_k`: the modes `shapes` with
/// squared frequencies `stiffness` at the amplitudes `a` against the full model's elastic forces
/// `f` at `Σ a_k φ_k` (over the same degrees of freedom); 0 at rest.
pub(crate) fn relative_error(shapes: &[Vec<f64>], stiffness: &[f64], a: &[f64], force: &[f64]) -> f64 {
    let (mut error, mut norm) = (0.0, 0.0);
    for ((phi, &lambda), &x) in shapes.iter().zip(stiffness).zip(a) {
        let r = super::dot(phi, force) - lambda * x;
        error += r * r / lambda;
        norm += lambda * x * x;
    }
    if norm > 0.0 {
        (error / norm).sqrt()
    } else {
        0.0
    }
}
