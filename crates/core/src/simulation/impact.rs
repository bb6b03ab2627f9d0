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
//! alternate between entering and leaving the wall from one sub-step to the next. The rigid-turn
//! guess then puts the arc into the wall, and the secant of a point that enters (`∝ a²/(a + b)` in
//! its penetration `a`) is flat near the solution, which Newton approaches by halving. The full
//! body's guess inside such an impact extrapolates the alternation from the sub-step ends kept
//! here ([`ImpactTrail`]; the guess in `full::guess`).
//!
//! With `contact.method = "penalty"` the steps are not split (the tutorial's way); the events are
//! then located between step ends only.

use super::events::{ContactEvent, ContactEventKind, ContactPhase, ImpactTrail};
use super::interface::Ask;
use super::{Simulation, StepRecord};
use crate::config::WallKind;
use crate::error::Error;
use crate::error::NewtonError;
use crate::terms::WallContact;

/// The impacts of a simulation: the events so far, the impact in progress and its sub-step ends,
/// and the records of the sub-steps inside impacts.
#[derive(Debug, Default)]
pub(super) struct Impacts {
    /// Impacts so far (counted when the head first penetrates the wall).
    pub count: usize,
    /// Contact events so far (append-only within a run: roll-backs truncate it).
    pub events: Vec<ContactEvent>,
    /// The impact in progress.
    pub phase: Option<ContactPhase>,
    /// The sub-step ends of the impact in progress.
    pub trail: ImpactTrail,
    /// Whether the sub-steps inside impacts are recorded ([`Simulation::record_impacts`]).
    pub recording: bool,
    /// The records of the sub-steps inside impacts not yet taken (roll-backs truncate it).
    pub records: Vec<StepRecord>,
}

impl Impacts {
    /// What a step of the body is asked about the impacts: the sub-step ends of an impact resolved
    /// in sub-steps, and the events so far.
    pub fn ask(&self, correct: bool, step: usize, last_iterations: usize) -> Ask<'_> {
        Ask {
            correct,
            step,
            last_iterations,
            impact: self.phase.filter(|p| p.resolved).map(|_| &self.trail),
            events: &self.events,
        }
    }
}

impl Simulation {
    /// Whether impacts are located and resolved in sub-steps (see the module doc).
    pub(super) fn resolves_impacts(&self) -> bool {
        self.model.wall.as_ref().is_some_and(|w| !w.end_point)
    }

    /// Contact events so far.
    pub fn contact_events(&self) -> &[ContactEvent] {
        &self.contact.events
    }

    /// Impacts so far (counted when the head first penetrates the wall).
    pub fn impacts(&self) -> usize {
        self.contact.count
    }

    /// Whether the head is in an impact now.
    pub fn in_contact(&self) -> bool {
        self.contact.phase.is_some_and(|p| p.penetrated)
    }

    /// The impact-resolution level of an output step: advances by `dt` resolving impacts (see the
    /// module doc) in sub-steps ([`Simulation::substep`]); returns the Newton iterations.
    pub(super) fn resolve_impacts(&mut self, dt: f64) -> Result<usize, Error> {
        let (step, t0) = (self.step + 1, self.now.state.t);
        let failed = |(source, dt): (NewtonError, f64)| Error::TimeStep {
            step,
            t: t0,
            dt,
            source,
        };
        let t_end = self.now.state.t + dt;
        let (mut its, mut landings) = (0, 0);
        // a remainder below a millionth of the step is rounding of the sub-step sum
        while t_end - self.now.state.t > 1e-9 * dt {
            let remaining = t_end - self.now.state.t;
            let (omega, alpha) = self.angular_rates();
            // a body that knows itself farther from the wall than twice its rigid flight over the
            // step can go (the reduced body) needs none of the contact's checks on the fields, if
            // it is clear at the end too (otherwise the step is taken again below, with them)
            if self.contact.phase.is_none() {
                let reach = 2.0
                    * self.model.length_scale()
                    * (omega.abs() * remaining + 0.5 * alpha.abs() * remaining * remaining);
                if self.body.clearance(&self.model).is_some_and(|c| c > reach) {
                    let before = self.rollback_point();
                    its += self.substep(remaining).map_err(failed)?;
                    if self.body.clearance(&self.model).is_some_and(|c| c > 0.0) {
                        continue;
                    }
                    self.roll_back(&before);
                }
            }
            let wall = self.model.wall.as_ref().expect("resolves_impacts checked the wall");
            let s = &self.now.state;
            let h = match self.contact.phase {
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
            its += self.substep(h).map_err(failed)?;
            let u0 = &before.snapshot.state.u;
            self.check_contact_step(step, t0, u0)?;
            let wall = self.model.wall.as_ref().expect("checked");
            if self.contact.phase.is_none() && apart && wall.in_contact(&self.now.state.u) {
                // a touch the rigid flight did not foresee: retake the step up to the crossing
                let crossing = wall.first_crossing(u0, &self.now.state.u).unwrap_or(1.0);
                if crossing > 1e-3 && crossing < 1.0 {
                    self.roll_back(&before);
                    its += self.substep(crossing * h).map_err(failed)?;
                    self.check_contact_step(step, t0, u0)?;
                    self.begin_contact();
                } else {
                    self.begin_contact();
                    self.contact_progress(u0, h);
                }
                continue;
            }
            if self.contact.phase.is_some() {
                self.contact_progress(u0, h);
                if self.contact.phase.is_some() {
                    self.contact.trail.push(before.snapshot.state.t, u0, self.now.state.t);
                } else {
                    self.contact.trail = ImpactTrail::default();
                }
                if self.contact.recording && self.now.state.t < t_end - 1e-9 * dt {
                    // inside the step (its end is the output step's own record)
                    let record = self.record(its);
                    self.contact.records.push(record);
                }
            }
        }
        Ok(its)
    }

    /// Records the state after every sub-step inside an impact (not at the output step's end,
    /// which has its record), to be taken with [`Simulation::take_impact_records`]: an impact of
    /// about 2 ms between output rows 10 ms apart is otherwise seen only where a row happens to
    /// fall inside it. Off by default (a record costs the nodal stresses).
    pub fn record_impacts(&mut self, on: bool) {
        self.contact.recording = on;
        if !on {
            self.contact.records.clear();
        }
    }

    /// The records of the sub-steps inside impacts since the last call, in time order (see
    /// [`Simulation::record_impacts`]); the Newton iterations of each are those of its output step
    /// so far.
    pub fn take_impact_records(&mut self) -> Vec<StepRecord> {
        std::mem::take(&mut self.contact.records)
    }

    /// The (sub)step just taken from `u0` (started at `t0`, the output step `step` in progress):
    /// a head that came round the deformable wall's face end is outside the model
    /// ([`WallContact::came_round`]), and a contact that the fixed sparsity pattern does not cover
    /// is an error naming it ([`WallContact::uncoupled_contact`]).
    pub(super) fn check_contact_step(&self, step: usize, t0: f64, u0: &[f64]) -> Result<(), Error> {
        let Some(wall) = self.model.wall.as_ref() else {
            return Ok(());
        };
        if let Some(message) = wall.came_round(u0, &self.now.state.u) {
            return Err(Error::OutsideModel { step, t: t0, message });
        }
        match wall.uncoupled_contact(&self.now.state.u) {
            Some(message) => Err(Error::ContactOutsidePattern {
                step,
                t: self.now.state.t,
                message,
            }),
            None => Ok(()),
        }
    }

    /// The sub-step of the impact in progress \[s\] (`None` between impacts and with
    /// `contact.method = "penalty"`, which does not split steps).
    pub fn contact_substep(&self) -> Option<f64> {
        self.contact.phase.filter(|p| p.resolved).map(|p| p.substep)
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
        self.contact.trail = ImpactTrail::default();
        self.contact.phase = Some(ContactPhase {
            substep,
            resolved: true,
            first_substep: substep,
            separated: None,
            touch: self.now.state.t,
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
        let u1 = &self.now.state.u;
        let force = wall.step_force(u0, u1);
        let (gap0, gap1) = (wall.smallest_gap(u0), wall.smallest_gap(u1));
        let normal = wall.normal_force(u1);
        let now = self.now.state.t;
        let (omega, _) = self.angular_rates();
        let theta = self.now.theta;
        let Some(mut phase) = self.contact.phase else {
            return;
        };
        phase.impulse += force * h;
        phase.penetration = phase.penetration.max(-gap1);
        phase.force = phase.force.max(normal);
        if !phase.penetrated && gap1 < 0.0 {
            phase.penetrated = true;
            self.contact.count += 1;
            self.contact.events.push(ContactEvent {
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
            self.contact.events.push(ContactEvent {
                time: left,
                kind: ContactEventKind::End,
                theta,
                omega,
                impulse: phase.impulse,
                penetration: phase.penetration,
                force: phase.force,
            });
            self.contact.phase = None;
            return;
        }
        if !phase.penetrated && gap1 > gap0 {
            // grazed and moving away without touching
            self.contact.phase = None;
            return;
        }
        self.contact.phase = Some(phase);
    }

    /// Books a step of the penalty method (no sub-steps): events between step ends.
    pub(super) fn contact_step_ends(&mut self, u0: &[f64], h: f64) {
        let Some(wall) = self.model.wall.as_ref() else {
            return;
        };
        let (before, after) = (wall.in_contact(u0), wall.in_contact(&self.now.state.u));
        if !before && !after && self.contact.phase.is_none() {
            return;
        }
        if self.contact.phase.is_none() {
            self.contact.phase = Some(ContactPhase {
                substep: h,
                resolved: false,
                first_substep: h,
                separated: None,
                touch: self.now.state.t - h + h * wall.first_crossing(u0, &self.now.state.u).unwrap_or(1.0),
                penetrated: false,
                impulse: 0.0,
                penetration: 0.0,
                force: 0.0,
            });
        }
        self.contact_progress(u0, h);
    }
}
