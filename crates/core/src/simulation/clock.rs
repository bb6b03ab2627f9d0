//! The clock of a [`Simulation`](super::Simulation): the time of the state as `base + count · dt`
//! over a run of equal steps ([`Clock`]).

/// The time of the state as `base + count · dt`: over a run of steps of the same `dt` the time
/// is computed, not accumulated (`n · dt` exactly for a run from 0, as `advance` always did), and
/// any other step starts a new run at the time reached.
#[derive(Clone, Copy, Debug)]
pub(super) struct Clock {
    pub(super) base: f64,
    pub(super) dt: f64,
    pub(super) count: u64,
}

/// Equal bit for bit (`dt` is NaN before a run).
impl PartialEq for Clock {
    fn eq(&self, other: &Self) -> bool {
        self.base.to_bits() == other.base.to_bits()
            && self.dt.to_bits() == other.dt.to_bits()
            && self.count == other.count
    }
}

impl Clock {
    /// t = 0, no run yet.
    pub(super) const START: Self = Self {
        base: 0.0,
        dt: f64::NAN,
        count: 0,
    };

    /// The time \[s\].
    pub(super) fn time(&self) -> f64 {
        if self.count == 0 {
            self.base
        } else {
            self.base + self.count as f64 * self.dt
        }
    }

    /// The clock after one more step of `dt`.
    pub(super) fn after(&self, dt: f64) -> Self {
        if dt.to_bits() == self.dt.to_bits() {
            Self {
                count: self.count + 1,
                ..*self
            }
        } else {
            Self {
                base: self.time(),
                dt,
                count: 1,
            }
        }
    }

    /// A clock standing at exactly `t`.
    pub(super) fn at(t: f64) -> Self {
        Self {
            base: t,
            dt: f64::NAN,
            count: 0,
        }
    }
}
