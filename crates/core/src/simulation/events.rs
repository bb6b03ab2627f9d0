//! The records of impacts: contact events ([`ContactEvent`]), the impact in progress
//! ([`ContactPhase`]) and its last sub-step ends ([`ImpactTrail`]). Plain data, kept by the
//! stepper (`impact`), saved in snapshots and read by the bodies' steps.

/// Start or end of an impact.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactEventKind {
    /// The head touches the wall.
    Start,
    /// The head leaves it.
    End,
}

/// One contact event.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactEvent {
    /// Time \[s\].
    pub time: f64,
    /// Start or end.
    pub kind: ContactEventKind,
    /// Proxy angle at the event's step end \[rad\].
    pub theta: f64,
    /// Angular velocity at the event's step end \[rad/s\].
    pub omega: f64,
    /// Impulse of the wall on the head over the impact \[N s\] (0 at its start).
    pub impulse: f64,
    /// Largest penetration over the impact at the sub-step ends \[m\] (0 at its start).
    pub penetration: f64,
    /// Largest normal force of the wall over the impact at the sub-step ends \[N\] (0 at its start).
    pub force: f64,
}

/// An impact in progress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ContactPhase {
    /// Sub-step length \[s\].
    pub substep: f64,
    /// Whether the impact is resolved in sub-steps (not with `contact.method = "penalty"`).
    pub resolved: bool,
    /// The first sub-step, `δ_max / (v · substeps)` \[s\].
    pub first_substep: f64,
    /// When the head last left the wall, if it has not come back \[s\].
    pub separated: Option<f64>,
    /// Time of the touch \[s\].
    pub touch: f64,
    /// Whether a point has penetrated yet (the impact counts from then).
    pub penetrated: bool,
    /// Impulse so far \[N s\].
    pub impulse: f64,
    /// Largest penetration so far \[m\].
    pub penetration: f64,
    /// Largest normal force so far \[N\].
    pub force: f64,
}

/// The sub-step ends of the impact in progress before the current state, for the predictor of a
/// chattering contact (see the module doc).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct ImpactTrail {
    /// `(t, u)` at the ends of the (at most two) sub-steps before the last one, oldest first.
    pub earlier: Vec<(f64, Vec<f64>)>,
    /// When the last sub-step ended \[s\]: the trail leads to the current state only if it is now.
    pub end: f64,
}

impl ImpactTrail {
    /// Appends the sub-step from `(t0, u0)` that ended at `t1`.
    pub fn push(&mut self, t0: f64, u0: &[f64], t1: f64) {
        if self.earlier.len() == 2 {
            let mut oldest = self.earlier.remove(0);
            oldest.0 = t0;
            oldest.1.copy_from_slice(u0);
            self.earlier.push(oldest);
        } else {
            self.earlier.push((t0, u0.to_vec()));
        }
        self.end = t1;
    }
}
