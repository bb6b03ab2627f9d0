//! Impacts with the wall: located in time and resolved in sub-steps of the contact's own time scale.
//!
//! With `contact.method = "energy-consistent"` (the energy-momentum scheme with the secant contact
//! force of [`crate::terms::contact`]), one output step of length `Δt` is advanced as follows:
//!
//! 1. **Apart**: every contact point moves on its circle about the pivot as the body turns rigidly
//!    by `ω s + ½ α s²` from the step's start (the best-fit rates), so the first time a point
//!    reaches the wall's face is known in closed form ([`WallContact::first_touch`]). No touch within the step: one step. A touch at `s`: a step
//!    of length `s` lands the head on the wall; predicted again from there (the step's trajectory
//!    is not exactly the rigid flight), up to four landings bring the head to within `1e-6 Δt` of the
//!    touch (to a fraction of a micrometre).
//! 2. **In contact** (from the touch until no point penetrates): sub-steps of length
//!    `h = τ / contact.substeps`, where `τ = δ_max / v` is the contact's time scale, `v` the approach
//!    speed at the touch and `δ_max` the penetration at which the contact energy would absorb the
//!    kinetic energy of the pendulum's effective mass at the contact, `m = I / y²` (`I` about the
//!    pivot, `y` the contact point's depth below it). For the head's arc of radius `R` against the
//!    flat face with the penalty pressure `k g`, the force is `k t (4/3) √(2R) δ^{3/2}` and the
//!    energy `k t (8/15) √(2R) δ^{5/2}` (a cylinder on a plane). The tutorial's 20° swing against
//!    `k = 2e10` gives `δ_max` = 397 µm and `τ` = 0.72 ms, so 10 sub-steps of 72 µs; the converged
//!    impact lasts 2.1 ms.
//!    A compliant body yields before the penalty does: its own time scale is half the quarter
//!    period `(π/2) √(m / k_b)` of the effective mass on the body's contact stiffness, estimated
//!    as that of a plane-stress line contact, `k_b = (π/4) E t`; `τ` is the larger of the two. For
//!    steel the penalty's governs (`k_b` = 1.6e9 N/m, 11 µs); for the soft pendulum of E = 1 MPa
//!    the body's (2.75 ms against 0.3 ms). Against the deformable wall both bodies yield, as two
//!    springs in series, `1/k_b = 1/k_pendulum + 1/k_block`, each `(π/4) E t` with its own modulus
//!    and thickness (the block's from `[wall]`): the softer of the two governs (a rubber block of
//!    E = 10 MPa against the steel pendulum: `k_b` = 7.9e4 N/m, 2.4 ms against the penalty's 0.72 ms). Half, because the stiff penalty still acts at the
//!    contact points: Newton failed to converge in the soft pendulum's second impact at a tenth of
//!    the whole quarter period and converges at a tenth of its half.
//! 3. The impact ends when no point has penetrated for the time `τ` (a body ringing after the blow
//!    may touch again at once; that is the same impact); its end time is when the largest
//!    penetration last returned to zero. The rest of the output step follows in one step (or
//!    again 1. if the head comes back).
//!
//! Should a step that started apart end inside the wall anyway (a touch the rigid flight did not
//! foresee), it is taken again up to the first crossing of the straight path between its ends
//! ([`WallContact::first_crossing`]). Every impact is reported by its start (the touch) and end (the
//! time at which the largest penetration returns to zero, interpolated in the last sub-step) with
//! the impulse of the wall over it ([`ContactEvent`]).
//!
//! **A chattering contact.** Where the penalty is far stiffer than the body (a soft head, or a
//! stiff `contact.stiffness`), the arc's points have a period of microseconds against sub-steps
//! of tens: the midpoint rule maps that motion to a phase near π per sub-step, and the points
//! alternate between entering and leaving the wall from one sub-step to the next (measured on a
//! 24 MPa head at `k = 7e12 N/m³`: 15 of 16 penetrating points swap every sub-step, by about a
//! micrometre). The rigid-rotation predictor then puts the arc 0.1 mm into the wall (a first
//! Newton correction of 1e3 J), and the secant of a point that enters (`∝ a²/(a + b)` in its
//! penetration `a`) is flat near the solution, which Newton approaches by halving: 11–16
//! iterations per sub-step. Once the smallest gap has alternated over the last three sub-step
//! ends, the predictor takes the state two sub-steps back, moved on by the drift measured over
//! the two sub-steps before (the extrapolation exact for a motion linear in time plus an
//! alternation from one sub-step to the next):
//!
//! ```text
//! u_{n+1} ≈ u_{n−1} + (t_{n+1} − t_{n−1}) / (t_n − t_{n−2}) · (u_n − u_{n−2})
//! ```
//!
//! and the tangent is made afresh (the previous sub-step's factorisation has the entering and
//! leaving points' slopes swapped): 6–8 iterations ([`Simulation::chatter_guess`]).
//!
//! With `contact.method = "penalty"` the steps are not split (the tutorial's way); the events are
//! then located between step ends only.

use super::{Simulation, StepRecord};
use crate::config::WallKind;
use crate::error::NewtonError;
use crate::terms::WallContact;
use crate::Error;

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
pub(super) struct ContactPhase {
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
pub(super) struct ImpactTrail {
    /// `(t, u)` at the ends of the (at most two) sub-steps before the last one, oldest first.
    pub earlier: Vec<(f64, Vec<f64>)>,
    /// When the last sub-step ended \[s\]: the trail leads to the current state only if it is now.
    pub end: f64,
}

impl ImpactTrail {
    /// Appends the sub-step from `(t0, u0)` that ended at `t1`.
    fn push(&mut self, t0: f64, u0: &[f64], t1: f64) {
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

impl Simulation {
    /// Whether impacts are located and resolved in sub-steps (see the module doc).
    pub(super) fn resolves_impacts(&self) -> bool {
        self.model.wall.as_ref().is_some_and(|w| !w.end_point)
    }

    /// Contact events so far.
    pub fn contact_events(&self) -> &[ContactEvent] {
        &self.events
    }

    /// Impacts so far (counted when the head first penetrates the wall).
    pub fn impacts(&self) -> usize {
        self.impacts
    }

    /// Whether the head is in an impact now.
    pub fn in_contact(&self) -> bool {
        self.contact_phase.is_some_and(|p| p.penetrated)
    }

    /// Advances by `dt` resolving impacts (see the module doc); returns the Newton iterations or the
    /// failure and the length of the step that failed.
    pub(super) fn advance_resolving(&mut self, dt: f64) -> Result<usize, Error> {
        let (step, t0) = (self.step + 1, self.state.t);
        let failed = |(source, dt): (NewtonError, f64)| Error::TimeStep {
            step,
            t: t0,
            dt,
            source,
        };
        let t_end = self.state.t + dt;
        let (mut its, mut landings) = (0, 0);
        // a remainder below a millionth of the step is rounding of the sub-step sum
        while t_end - self.state.t > 1e-9 * dt {
            let remaining = t_end - self.state.t;
            let (omega, alpha) = self.angular_rates();
            // a reduced body farther from the wall than twice its rigid flight over the step can
            // go needs none of the contact's checks on the fields, if it is clear at the end too
            // (otherwise the step is taken again below, with them)
            if self.contact_phase.is_none() {
                let reach = 2.0
                    * self.model.length_scale()
                    * (omega.abs() * remaining + 0.5 * alpha.abs() * remaining * remaining);
                if self.reduced_clearance().is_some_and(|c| c > reach) {
                    let before = self.rollback_point();
                    its += self.advance_by(remaining).map_err(failed)?;
                    if self.reduced_clearance().is_some_and(|c| c > 0.0) {
                        continue;
                    }
                    self.roll_back(&before);
                }
            }
            let wall = self.model.wall.as_ref().expect("resolves_impacts checked the wall");
            let s = &self.state;
            let h = match self.contact_phase {
                Some(phase) => phase.substep.min(remaining),
                None if wall.in_contact(&s.u) => {
                    self.begin_contact();
                    continue;
                }
                None => match wall.first_touch(&s.u, omega, alpha, remaining) {
                    // land on the wall. The landing step's trajectory differs a little from the
                    // rigid flight (12 µm short of the wall for the tutorial's swing), so the touch
                    // is predicted again from where it landed, at most 4 times, until it is within
                    // 1e-6 of the step: that is the impact's start.
                    Some(touch) if touch > 1e-6 * dt && landings < 4 => {
                        landings += 1;
                        touch
                    }
                    Some(_) => {
                        self.begin_contact();
                        continue;
                    }
                    None => remaining,
                },
            };
            let h = if remaining - h < 1e-6 * dt { remaining } else { h };
            let apart = !wall.in_contact(&s.u);
            let before = self.rollback_point();
            its += self.advance_by(h).map_err(failed)?;
            let u0 = &before.snapshot.state.u;
            self.check_contact_step(step, t0, u0)?;
            let wall = self.model.wall.as_ref().expect("checked");
            if self.contact_phase.is_none() && apart && wall.in_contact(&self.state.u) {
                // a touch the rigid flight did not foresee: retake the step up to the crossing
                let crossing = wall.first_crossing(u0, &self.state.u).unwrap_or(1.0);
                if crossing > 1e-3 && crossing < 1.0 {
                    self.roll_back(&before);
                    its += self.advance_by(crossing * h).map_err(failed)?;
                    self.check_contact_step(step, t0, u0)?;
                    self.begin_contact();
                } else {
                    self.begin_contact();
                    self.contact_progress(u0, h);
                }
                continue;
            }
            if self.contact_phase.is_some() {
                self.contact_progress(u0, h);
                if self.contact_phase.is_some() {
                    self.impact_trail.push(before.snapshot.state.t, u0, self.state.t);
                } else {
                    self.impact_trail = ImpactTrail::default();
                }
                if self.recording_impacts && self.state.t < t_end - 1e-9 * dt {
                    // inside the step (its end is the output step's own record)
                    let record = self.record(its);
                    self.impact_records.push(record);
                }
            }
        }
        Ok(its)
    }

    /// The predictor of a sub-step of length `dt` inside a chattering impact (see the module doc),
    /// or `None`: not in an impact resolved in sub-steps, fewer than three sub-steps of it behind
    /// the current state, or a smallest gap that did not alternate over them.
    pub(super) fn chatter_guess(&self, dt: f64) -> Option<Vec<f64>> {
        self.contact_phase.filter(|p| p.resolved)?;
        let trail = &self.impact_trail;
        let wall = self.model.wall.as_ref()?;
        let [(t2, u2), (t1, u1)] = trail.earlier.as_slice() else {
            return None;
        };
        let (t0, u0) = (self.state.t, &self.state.u);
        if trail.end != t0 {
            return None;
        }
        let [g2, g1, g0] = [u2, u1, u0].map(|u| wall.smallest_gap(u));
        if (g0 - g1) * (g1 - g2) >= 0.0 {
            return None;
        }
        let drift = (t0 + dt - t1) / (t0 - t2);
        Some(
            u1.iter()
                .zip(u0)
                .zip(u2)
                .map(|((a, b), c)| a + drift * (b - c))
                .collect(),
        )
    }

    /// Records the state after every sub-step inside an impact (not at the output step's end,
    /// which has its record), to be taken with [`Simulation::take_impact_records`]: an impact of
    /// about 2 ms between output rows 10 ms apart is otherwise seen only where a row happens to
    /// fall inside it. Off by default (a record costs the nodal stresses).
    pub fn record_impacts(&mut self, on: bool) {
        self.recording_impacts = on;
        if !on {
            self.impact_records.clear();
        }
    }

    /// The records of the sub-steps inside impacts since the last call, in time order (see
    /// [`Simulation::record_impacts`]); the Newton iterations of each are those of its output step
    /// so far.
    pub fn take_impact_records(&mut self) -> Vec<StepRecord> {
        std::mem::take(&mut self.impact_records)
    }

    /// The (sub)step just taken from `u0` (started at `t0`, the output step `step` in progress):
    /// a head that came round the deformable wall's face end is outside the model
    /// ([`WallContact::came_round`]), and a contact that the fixed sparsity pattern does not cover
    /// is an error naming it ([`WallContact::uncoupled_contact`]).
    pub(super) fn check_contact_step(&self, step: usize, t0: f64, u0: &[f64]) -> Result<(), Error> {
        let Some(wall) = self.model.wall.as_ref() else {
            return Ok(());
        };
        if let Some(message) = wall.came_round(u0, &self.state.u) {
            return Err(Error::OutsideModel { step, t: t0, message });
        }
        match wall.uncoupled_contact(&self.state.u) {
            Some(message) => Err(Error::ContactOutsidePattern {
                step,
                t: self.state.t,
                message,
            }),
            None => Ok(()),
        }
    }

    /// The sub-step of the impact in progress \[s\] (`None` between impacts and with
    /// `contact.method = "penalty"`, which does not split steps).
    pub fn contact_substep(&self) -> Option<f64> {
        self.contact_phase.filter(|p| p.resolved).map(|p| p.substep)
    }

    /// Starts an impact at the current state: its sub-step from the contact's time scale.
    fn begin_contact(&mut self) {
        let (omega, _) = self.angular_rates();
        let m = &self.model;
        let g = &m.config.geometry;
        // the contact point's depth below the pivot and the approach speed there
        let depth = g.head_center_distance;
        let speed = (omega.abs() * depth).max(1e-3);
        let mass = m.inertia_pivot() / (depth * depth);
        let k = m.config.contact.stiffness * g.thickness;
        let energy = 0.5 * mass * speed * speed;
        let delta = (energy / (k * (8.0 / 15.0) * (2.0 * g.head_radius).sqrt())).powf(0.4);
        let line_stiffness =
            |youngs_modulus: f64, thickness: f64| std::f64::consts::FRAC_PI_4 * youngs_modulus * thickness;
        let pendulum = line_stiffness(m.config.material.youngs_modulus, g.thickness);
        let w = &m.config.wall;
        // the two bodies in contact yield in series; the softer governs
        let body = match w.kind {
            WallKind::Deformable => 1.0 / (1.0 / pendulum + 1.0 / line_stiffness(w.youngs_modulus, w.thickness)),
            WallKind::None | WallKind::Rigid => pendulum,
        };
        let tau = (delta / speed).max(std::f64::consts::FRAC_PI_4 * (mass / body).sqrt());
        let substep = tau / m.config.contact.substeps as f64;
        self.impact_trail = ImpactTrail::default();
        self.contact_phase = Some(ContactPhase {
            substep,
            resolved: true,
            first_substep: substep,
            separated: None,
            touch: self.state.t,
            penetrated: false,
            impulse: 0.0,
            penetration: 0.0,
            force: 0.0,
        });
    }

    /// Books the (sub)step of length `h` from `u0` into the impact in progress: the impulse, the
    /// start event at the first penetration, the end event when no point penetrates any more.
    fn contact_progress(&mut self, u0: &[f64], h: f64) {
        let wall: &WallContact = self.model.wall.as_ref().expect("checked");
        let u1 = &self.state.u;
        let force = wall.step_force(u0, u1);
        let (gap0, gap1) = (wall.smallest_gap(u0), wall.smallest_gap(u1));
        let normal = wall.normal_force(u1);
        let now = self.state.t;
        let (omega, _) = self.angular_rates();
        let theta = self.theta;
        let Some(mut phase) = self.contact_phase else {
            return;
        };
        phase.impulse += force * h;
        phase.penetration = phase.penetration.max(-gap1);
        phase.force = phase.force.max(normal);
        if !phase.penetrated && gap1 < 0.0 {
            phase.penetrated = true;
            self.impacts += 1;
            self.events.push(ContactEvent {
                time: phase.touch,
                kind: ContactEventKind::Start,
                theta,
                omega,
                impulse: 0.0,
                penetration: 0.0,
                force: 0.0,
            });
        }
        if phase.penetrated && gap1 >= 0.0 && phase.separated.is_none() {
            // the largest penetration returned to zero within this sub-step
            let fraction = if gap0 < 0.0 { gap0 / (gap0 - gap1) } else { 0.0 };
            phase.separated = Some(now - h + fraction * h);
        } else if gap1 < 0.0 {
            phase.separated = None;
        }
        // the impact ends when the head has stayed off the wall for the contact's time scale (a
        // body ringing after the blow may touch again at once: that is the same impact)
        let release = phase.first_substep * self.model.config.contact.substeps as f64;
        if let Some(left) = phase.separated.filter(|&left| now - left >= release || !phase.resolved) {
            self.events.push(ContactEvent {
                time: left,
                kind: ContactEventKind::End,
                theta,
                omega,
                impulse: phase.impulse,
                penetration: phase.penetration,
                force: phase.force,
            });
            self.contact_phase = None;
            return;
        }
        if !phase.penetrated && gap1 > gap0 {
            // grazed and moving away without touching
            self.contact_phase = None;
            return;
        }
        self.contact_phase = Some(phase);
    }

    /// Books a step of the penalty method (no sub-steps): events between step ends.
    pub(super) fn contact_step_ends(&mut self, u0: &[f64], h: f64) {
        let Some(wall) = self.model.wall.as_ref() else {
            return;
        };
        let (before, after) = (wall.in_contact(u0), wall.in_contact(&self.state.u));
        if !before && !after && self.contact_phase.is_none() {
            return;
        }
        if self.contact_phase.is_none() {
            self.contact_phase = Some(ContactPhase {
                substep: h,
                resolved: false,
                first_substep: h,
                separated: None,
                touch: self.state.t - h + h * wall.first_crossing(u0, &self.state.u).unwrap_or(1.0),
                penetrated: false,
                impulse: 0.0,
                penetration: 0.0,
                force: 0.0,
            });
        }
        self.contact_progress(u0, h);
    }
}
