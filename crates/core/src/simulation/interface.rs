//! What the stepper and a body exchange: what a step is asked with ([`Ask`]), what a step took
//! ([`Taken`]), and the body's part of a snapshot ([`BodySnapshot`]).

use std::sync::Arc;

use super::events::{ContactEvent, ImpactTrail};
use crate::newton::FactorState;
use crate::reduced::ReducedState;

/// What a step of the body is asked with, besides the model and the current state.
pub(crate) struct Ask<'a> {
    /// Whether Newton may correct slow iterations by GMRES (the full body).
    pub correct: bool,
    /// Steps done before this one.
    pub step: usize,
    /// Newton iterations of the last output step.
    pub last_iterations: usize,
    /// The sub-step ends of the impact in progress, when it is resolved in sub-steps (the full
    /// body's guess inside a chattering contact).
    pub impact: Option<&'a ImpactTrail>,
    /// The contact events so far.
    pub events: &'a [ContactEvent],
}

/// A step taken: Newton iterations and numeric factorisations.
pub(crate) struct Taken {
    /// Newton iterations.
    pub iterations: usize,
    /// Numeric factorisations of the full tangent.
    pub factorizations: usize,
}

/// A body's part of a snapshot: what of the body determines the steps after it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BodySnapshot {
    /// `(t, α)` at the start of the previous (sub)step (the full body's predictor).
    pub previous_alpha: Option<(f64, f64)>,
    /// The full body's reusable factorisation.
    pub factor: Option<Arc<FactorState>>,
    /// The reduced body's coordinates and momenta.
    pub reduced: Option<ReducedState>,
}
