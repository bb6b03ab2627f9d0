//! The body of a [`Simulation`](super::Simulation), of either kind, behind one interface: the
//! full finite-element body (`full`: every node's displacement, a time scheme of
//! [`crate::scheme`] solved by Newton) or the reduced body (`reduced`: a floating frame and a few
//! modes, [`crate::reduced`]). The stepper asks the body for its step, its rigid-body rates,
//! energies, contact readings, stresses, fields and snapshots, and never which kind it is.
//!
//! **Why an enum.** The two kinds are known when the crate is compiled and there will not be a
//! third from outside; each method below is one `match` that hands the call on, so the kinds'
//! differences live in their own files and this is the only place that names both. The step is
//! the hot path (a reduced step takes microseconds): a `match` is a direct call the compiler can
//! inline, and a snapshot's part of the body is plain data ([`BodySnapshot`]).

use super::full::Full;
use super::interface::{Ask, BodySnapshot, Taken};
use super::measures::Kinematics;
use super::reduced::{Reduced, Stored};
use super::Now;
use crate::config::{Config, ModelKind};
use crate::error::Error;
use crate::error::NewtonError;
use crate::model::{Fingerprint, Model};
use crate::newton::Timings;
use crate::post::NodalStress;
use crate::reduced::ReducedState;

/// The body: full or reduced (see the module doc).
pub(crate) enum Dynamics {
    /// The full finite-element body.
    Full(Box<Full>),
    /// The reduced body.
    Reduced(Box<Reduced>),
}

/// What a body can prepare while its model's operators are built (see [`Model::build_beside`]).
pub(crate) type Prepared = Option<Stored>;

impl Dynamics {
    /// The work a body of `config` does beside its model's set-up, from the model's fingerprint.
    pub fn prepare(config: &Config, fingerprint: &Fingerprint) -> Prepared {
        match config.model.kind {
            ModelKind::Full => None,
            ModelKind::Reduced => Reduced::prepare(config, fingerprint),
        }
    }

    /// The body of the model's configuration (`model.kind`).
    pub fn new(model: &Model, prepared: Prepared) -> Result<Self, Error> {
        Ok(match model.config.model.kind {
            ModelKind::Full => Self::Full(Box::new(Full::new(model)?)),
            ModelKind::Reduced => Self::Reduced(Box::new(Reduced::new(model, prepared)?)),
        })
    }

    /// Sets the body's initial state from the rigid initial state in `now` (the full body's
    /// elastic equilibrium, the reduced body's coordinates).
    pub fn initialize(&mut self, model: &Model, now: &mut Now) -> Result<(), Error> {
        match self {
            Self::Full(b) => b.initialize(model, now),
            Self::Reduced(b) => {
                b.initialize(model, now);
                Ok(())
            }
        }
    }

    /// Whether its steps run on the pool that computes the elements (a pass over the elements to
    /// share; a reduced step has none and runs on the caller's thread).
    pub fn steps_on_pool(&self) -> bool {
        matches!(self, Self::Full(_))
    }

    /// Takes one step of `dt` from `now` (on success `now` is its end; on failure nothing changed).
    pub fn step(&mut self, model: &Model, now: &mut Now, dt: f64, ask: &Ask) -> Result<Taken, NewtonError> {
        match self {
            Self::Full(b) => b.step(model, now, dt, ask),
            Self::Reduced(b) => b.step(model, now, dt, ask),
        }
    }

    /// Whether an attempt that fails where no halving is left is tried once more without the
    /// GMRES correction.
    pub fn retries_uncorrected(&self) -> bool {
        match self {
            Self::Full(b) => b.retries_uncorrected(),
            Self::Reduced(_) => false,
        }
    }

    /// Prepares, after an output step, what the next step starts from and the outputs read.
    pub fn after_output_step(&mut self, model: &Model, now: &mut Now, step: usize) {
        if let Self::Full(b) = self {
            b.after_output_step(model, now, step);
        }
    }

    /// The rigid-body measures of the current state (cached in `now` until it changes).
    pub fn kinematics(&mut self, model: &Model, now: &mut Now, step: usize) -> Kinematics {
        if let Some(k) = now.rates {
            return k;
        }
        let k = match self {
            Self::Full(b) => b.kinematics(model, now, step),
            Self::Reduced(b) => b.kinematics(model, now),
        };
        now.rates = Some(k);
        k
    }

    /// Makes what [`Dynamics::energies`] reads of the current state if it is not made yet.
    pub fn prepare_energies(&mut self, model: &Model, now: &Now) {
        if let Self::Full(b) = self {
            b.prepare_energies(model, now);
        }
    }

    /// `[strain, gravity, contact]` energy of the current state \[J\].
    pub fn energies(&self, model: &Model, now: &Now) -> [f64; 3] {
        match self {
            Self::Full(b) => b.energies(model, now),
            Self::Reduced(b) => b.energies(model, now),
        }
    }

    /// The gap of the head's arc to the wall \[m\] (see `Simulation::gap`).
    pub fn gap(&self, model: &Model, now: &Now) -> f64 {
        match self {
            Self::Full(_) => super::measures::gap_of_fields(model, &now.state.u),
            Self::Reduced(b) => b.gap(model, now),
        }
    }

    /// The wall's normal force on the head \[N\] (see `Simulation::contact_force`).
    pub fn contact_force(&self, model: &Model, now: &Now) -> f64 {
        match self {
            Self::Full(_) => super::measures::contact_force_of_fields(model, &now.state.u),
            Self::Reduced(b) => b.contact_force(model, now),
        }
    }

    /// Nodal stresses of the current state.
    pub fn nodal_stress(&self, model: &Model, now: &Now) -> NodalStress {
        match self {
            Self::Full(_) => model.nodal_stress(&now.state.u),
            Self::Reduced(b) => b.nodal_stress(),
        }
    }

    /// The largest nodal von Mises stress of the current state \[Pa\].
    pub fn von_mises_max(&mut self, model: &Model, now: &Now) -> f64 {
        match self {
            Self::Full(_) => model.max_von_mises(&now.state.u),
            Self::Reduced(b) => b.von_mises_max(),
        }
    }

    /// The nodal displacement and velocity of the current state (a reduced body's rebuilt from
    /// its coordinates on the first call after a step).
    pub fn fields<'a>(&'a self, now: &'a Now) -> [&'a [f64]; 2] {
        match self {
            Self::Reduced(b) => b.fields(now),
            Self::Full(_) => [&now.state.u, &now.state.v],
        }
    }

    /// Brings the fields in `now` up to the body's state, for the readers that take them from
    /// there (frames, the acceleration field).
    pub fn sync_fields(&mut self, now: &mut Now) {
        if let Self::Reduced(b) = self {
            b.sync_fields(now);
        }
    }

    /// The proxy angle of the current state \[rad\]: on `(−π, π]` for the full body, on the
    /// frame's branch for the reduced body.
    pub fn proxy_angle(&self, model: &Model, now: &Now) -> f64 {
        match self {
            Self::Full(_) => model.projection.angle(&now.state.u),
            Self::Reduced(b) => b.proxy_angle(),
        }
    }

    /// A lower bound of the body's distance to the wall \[m\] (positive: nothing touches), when
    /// the body knows one without its fields (the reduced body with a wall).
    pub fn clearance(&self, model: &Model) -> Option<f64> {
        match self {
            Self::Full(_) => None,
            Self::Reduced(b) => b.clearance(model),
        }
    }

    /// Whether a roll-back point must copy the fields (the reduced body without a wall keeps
    /// none: its coordinates are its state).
    pub fn rolls_back_fields(&self, model: &Model) -> bool {
        match self {
            Self::Full(_) => true,
            Self::Reduced(_) => model.wall.is_some(),
        }
    }

    /// The body's part of a snapshot.
    pub fn save(&self) -> BodySnapshot {
        match self {
            Self::Full(b) => b.save(),
            Self::Reduced(b) => b.save(),
        }
    }

    /// Returns the body to `snapshot`'s part (its fields are in `now` already).
    pub fn restore(&mut self, model: &Model, snapshot: &BodySnapshot) {
        match self {
            Self::Full(b) => b.restore(model, snapshot),
            Self::Reduced(b) => b.restore(snapshot),
        }
    }

    /// The reduced body's largest error estimate so far and when `(η, t)`; `None` for the full.
    pub fn error_estimate(&self) -> Option<(f64, f64)> {
        match self {
            Self::Full(_) => None,
            Self::Reduced(b) => b.error_estimate(),
        }
    }

    /// A warning raised since the last call (the reduced body's, when it does not apply).
    pub fn take_warning(&mut self) -> Option<String> {
        match self {
            Self::Full(_) => None,
            Self::Reduced(b) => b.take_warning(),
        }
    }

    /// The reduced body's coordinates and momenta; `None` for the full body.
    pub fn reduced_state(&self) -> Option<&ReducedState> {
        match self {
            Self::Full(_) => None,
            Self::Reduced(b) => Some(b.state()),
        }
    }

    /// Accumulated Newton timings (zero for the reduced body, which never assembles the full
    /// tangent).
    pub fn timings(&self) -> Timings {
        match self {
            Self::Full(b) => b.timings(),
            Self::Reduced(_) => Timings::default(),
        }
    }

    /// Nonzeros of the full body's factor (0 for the reduced body).
    pub fn factor_nnz(&self) -> usize {
        match self {
            Self::Full(b) => b.factor_nnz(),
            Self::Reduced(_) => 0,
        }
    }
}
