//! The `[output]` section: what a run writes and how often, with its rules.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

use super::ranges::{non_negative, range, Mistakes};

/// What a run writes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Output {
    /// Output folder; each run gets a fresh subfolder unless `--out` names one.
    pub dir: PathBuf,
    /// Offer every n-th step to the animations and the viewer (the last step is always offered);
    /// also the ParaView thinning unless `paraview_every` is set. The default, 4, gives 25 frames a
    /// simulated second at the default step of 10 ms, so that the animations play in real time at
    /// 25 frames a second, and the default run's outputs cost less than its steps; 1 keeps every
    /// step.
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
    /// torque, over the energy scale) exceeds this fraction; 0 switches the watchdog off (a NaN or
    /// an infinity stops a run all the same).
    pub energy_watchdog: f64,
}

impl Output {
    /// The ParaView thinning: `paraview_every`, or `every` when that is not set.
    pub fn paraview_stride(&self) -> usize {
        self.paraview_every.unwrap_or(self.every).max(1)
    }

    /// The `[output]` rules.
    pub(super) fn validate(&self, m: &mut Mistakes) {
        let o = self;
        if o.every == 0 {
            m.push("output.every", "output.every = 0: allowed range 1 and up");
        }
        if o.paraview_every == Some(0) {
            m.push(
                "output.paraview_every",
                "output.paraview_every = 0: allowed range 1 and up (output.paraview = false writes no frames)",
            );
        }
        m.check(non_negative(
            "output.energy_watchdog",
            o.energy_watchdog,
            "(a fraction of the energy scale; 0: off)",
        ));
        if let Some(mag) = o.magnification {
            if !(mag >= 0.0 && mag.is_finite()) {
                m.keep(range(
                    "output.magnification",
                    mag,
                    "magnification >= 0 (omit the key for automatic)",
                ));
            }
        }
        if o.max_frames < 2 {
            m.push(
                "output.max_frames",
                format!("output.max_frames = {}: allowed range 2 and up", o.max_frames),
            );
        }
    }
}

impl Default for Output {
    fn default() -> Self {
        Self {
            dir: PathBuf::from("results"),
            every: 4,
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
