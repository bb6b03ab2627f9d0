//! The steps of a run: how many of `time.dt`, and a shortened last one that lands on `time.end`.

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
    pub fn of(time: &pendulum_fem_core::config::Time) -> Self {
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
