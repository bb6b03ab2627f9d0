//! FMI 3.0 Co-Simulation: impacts as events, early return from `fmi3DoStep`, and event mode.
//!
//! The stepper locates every impact inside its step (the touch, found in closed form on the free
//! flight and landed on; [`pendulum_fem_core::simulation::ContactEvent`]) and reports its start in
//! its event list, the list the CLI writes to `events.csv`. An impact is *announced* to the master
//! when a `fmi3DoStep` passes its start:
//!
//! * **Early return** (`earlyReturnAllowed`): the internal steps are those of FMI 2.0 (the same
//!   split, so the same numbers). When an internal step reports the start of an impact not yet
//!   announced that lies after the communication point, the instance keeps the state the stepper
//!   reached at the internal step's end (the *continuation*), goes back to the start of the internal
//!   step that holds the impact's start and steps to exactly that time
//!   ([`Simulation::step_to`]), and returns early there. The next `fmi3DoStep` that reaches the
//!   internal step's end takes the continuation instead of stepping again, so the states at the
//!   communication points are bit for bit those of the FMI 2.0 FMU. A changed input (`tau`), or a
//!   communication step that ends before the interrupted internal step's end, drops the
//!   continuation: the FMU then steps on from the impact's start.
//! * **Without early return** the step goes on to its end; the impacts it passed are announced
//!   there.
//! * **Event mode** (`eventModeUsed`): a step that announced an impact returns
//!   `eventHandlingNeeded`; the discrete outputs `contact_count` (the impacts announced) and
//!   `impact` (the event is an impact) change in `fmi3UpdateDiscreteStates`, which settles in one
//!   call. Without event mode they change at the end of the `fmi3DoStep` (or at its early return).
//!   `impact` falls back to false at the end of the next step, as in the FMI 2.0 FMU.
//!
//! An impact whose touch lies in an earlier communication step but whose first penetration (when
//! the stepper counts it) falls into this one — a touch less than one contact sub-step
//! ([`Simulation::contact_substep`]) before a communication point — is announced at the end of
//! this step.

use pendulum_fem_core::simulation::{split, ContactEventKind};
use pendulum_fem_core::{Simulation, Snapshot};

use super::{Instance, Phase, Status};

/// What `fmi3InstantiateCoSimulation` asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EventSettings {
    /// `eventModeUsed`: the master enters event mode when the FMU asks (`eventHandlingNeeded`).
    pub event_mode_used: bool,
    /// `earlyReturnAllowed`: `fmi3DoStep` may return at an impact's start.
    pub early_return_allowed: bool,
}

/// The part of an FMI 3.0 instance's state that its FMU states save too.
#[derive(Clone, Debug, PartialEq)]
pub struct EventState {
    /// Impact starts announced to the master (the first so many start events of the stepper).
    pub announced: u64,
    /// Announced, awaiting `fmi3UpdateDiscreteStates` (event mode).
    pub pending: u64,
    /// The discrete output `contact_count`.
    pub count: i32,
    /// The discrete output `impact`.
    pub impact: bool,
    /// After an early return: the state at the end of the interrupted internal step (see the
    /// module doc).
    pub continuation: Option<Snapshot>,
}

/// The FMI 3.0 part of an instance.
pub(super) struct Events {
    pub settings: EventSettings,
    pub state: EventState,
}

impl Events {
    pub fn new(settings: EventSettings) -> Self {
        Self {
            settings,
            state: EventState {
                announced: 0,
                pending: 0,
                count: 0,
                impact: false,
                continuation: None,
            },
        }
    }
}

/// How a `fmi3DoStep` ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepEnd {
    /// `eventHandlingNeeded`: event mode is used and the step announced an impact.
    pub event_handling_needed: bool,
    /// `earlyReturn`: the step stopped at an impact's start.
    pub early_return: bool,
    /// `lastSuccessfulTime` \[s\]: the impact's start after an early return, else the step's end.
    pub last_successful_time: f64,
}

/// An early return found by the internal steps.
pub(super) struct Early {
    /// Index of the impact among the stepper's start events.
    pub index: usize,
    /// The state at the end of the interrupted internal step.
    pub continuation: Snapshot,
    /// Whether that internal step holds another impact's start after this one (then the FMU steps
    /// on from this one instead of taking the continuation).
    pub more: bool,
}

/// The times of the impact starts so far \[s, simulation time\].
pub(super) fn impact_starts(sim: &Simulation) -> Vec<f64> {
    sim.contact_events()
        .iter()
        .filter(|e| e.kind == ContactEventKind::Start)
        .map(|e| e.time)
        .collect()
}

impl Instance {
    /// The FMI 3.0 event part (present on FMI 3.0 instances, which alone call this).
    fn events_mut(&mut self) -> &mut Events {
        self.events.as_mut().expect("an FMI 3.0 instance")
    }

    /// The event settings of an FMI 3.0 instance (`None` for FMI 2.0).
    pub fn event_settings(&self) -> Option<EventSettings> {
        self.events.as_ref().map(|e| e.settings)
    }

    /// The discrete outputs `(contact_count, impact)` of an FMI 3.0 instance.
    pub(super) fn discrete_outputs(&self) -> Option<(i32, bool)> {
        self.events.as_ref().map(|e| (e.state.count, e.state.impact))
    }

    /// The event part of the state, for an FMU state.
    pub(super) fn event_state(&self) -> Option<EventState> {
        self.events.as_ref().map(|e| e.state.clone())
    }

    /// Sets the event part of the state from an FMU state of the same FMI version.
    pub(super) fn set_event_state(&mut self, state: Option<&EventState>) {
        if let (Some(events), Some(state)) = (self.events.as_mut(), state) {
            events.state = state.clone();
        }
    }

    /// At the end of initialisation: nothing announced beyond the stepper's impacts so far; event
    /// mode when it is used.
    pub(super) fn start_events(&mut self) {
        let Some(starts) = self.sim.as_ref().map(|sim| impact_starts(sim).len()) else {
            return;
        };
        let Some(events) = self.events.as_mut() else {
            return;
        };
        events.state = EventState {
            announced: starts as u64,
            pending: 0,
            count: starts as i32,
            impact: false,
            continuation: None,
        };
        if events.settings.event_mode_used {
            self.phase = Phase::EventMode;
        }
    }

    /// A changed input: a continuation computed with the old one no longer holds.
    pub(super) fn input_changed(&mut self) {
        if let Some(events) = self.events.as_mut() {
            events.state.continuation = None;
        }
    }

    /// `fmi3EnterEventMode`: from step mode, when event mode is used.
    pub fn enter_event_mode(&mut self) -> Status {
        if let Err(status) = self.check_phase("fmi3EnterEventMode", &[Phase::StepMode]) {
            return status;
        }
        if !self.events_mut().settings.event_mode_used {
            return self.error(
                "fmi3EnterEventMode: this instance was made with eventModeUsed = false \
                 (fmi3InstantiateCoSimulation); it handles its events inside fmi3DoStep",
            );
        }
        self.phase = Phase::EventMode;
        Status::Ok
    }

    /// `fmi3UpdateDiscreteStates`: publishes the impacts announced since the last update in the
    /// discrete outputs; settles in one call (returns `Ok(())`: no further update needed, no
    /// termination, no time event).
    pub fn update_discrete_states(&mut self) -> Status {
        if let Err(status) = self.check_phase("fmi3UpdateDiscreteStates", &[Phase::EventMode]) {
            return status;
        }
        let state = &mut self.events_mut().state;
        state.impact = state.pending > 0;
        state.pending = 0;
        state.count = state.announced as i32;
        Status::Ok
    }

    /// `fmi3EnterStepMode`: from event mode.
    pub fn enter_step_mode(&mut self) -> Status {
        if let Err(status) = self.check_phase("fmi3EnterStepMode", &[Phase::EventMode]) {
            return status;
        }
        self.phase = Phase::StepMode;
        Status::Ok
    }

    /// `fmi3DoStep(t, h)`: the FMI 2.0 step with impacts as events (see the module doc).
    pub fn do_step_with_events(&mut self, t: f64, h: f64) -> Result<StepEnd, Status> {
        let mut end = StepEnd {
            event_handling_needed: false,
            early_return: false,
            last_successful_time: t + h,
        };
        if !self.check_step("fmi3DoStep", t, h)? {
            return Ok(end);
        }
        let settings = self.events_mut().settings;
        let target = self.time() + h;
        let max_step = self.value_of(crate::variables::Role::MaxInternalStep);
        // a continuation reached within the stepper's rounding is reached
        let reach = split::STEP_SNAP * max_step;
        let sim = self.sim.as_mut().expect("built at exitInitializationMode");
        // the communication point in the stepper's time: impacts after it may return early
        let from = sim.time();
        let mut resumed = None;
        if let Some(continuation) = self.events.as_mut().and_then(|e| e.state.continuation.take()) {
            if self.start_time + continuation.time() <= target + reach {
                resumed = Some((sim.snapshot(), continuation.clone()));
                sim.restore(&continuation).expect("a snapshot of this model restores");
            }
        }
        let remaining = target - self.time();
        let early = if remaining > reach {
            // impacts need a wall (`wall_kind` 1 or 2, fixed since initialisation); without one
            // no snapshots are taken for them
            let wall = self.value_of(crate::variables::Role::WallKind) as i64 != 0;
            let watch = (settings.early_return_allowed && wall).then(|| {
                let announced = self.events_mut().state.announced as usize;
                (announced, from)
            });
            match self.internal_steps("fmi3DoStep", remaining, watch) {
                Ok(early) => early,
                Err(status) => {
                    // back to the state before the call, continuation included
                    if let Some((before, continuation)) = resumed {
                        let sim = self.sim.as_mut().expect("built");
                        sim.restore(&before).expect("a snapshot of this model restores");
                        self.events_mut().state.continuation = Some(continuation);
                    }
                    return Err(status);
                }
            }
        } else {
            None
        };
        let sim = self.sim.as_ref().expect("built");
        let announced = match &early {
            Some(e) => e.index + 1,
            None => impact_starts(sim).len(),
        } as u64;
        if early.is_some() {
            end.early_return = true;
            end.last_successful_time = self.time();
        }
        let state = &mut self.events_mut().state;
        let fresh = announced.saturating_sub(state.announced);
        state.announced = state.announced.max(announced);
        if settings.event_mode_used {
            state.pending += fresh;
            state.impact = false;
            end.event_handling_needed = state.pending > 0;
        } else {
            state.count = state.announced as i32;
            state.impact = fresh > 0;
        }
        state.continuation = early.filter(|e| !e.more).map(|e| e.continuation);
        self.invalidate();
        Ok(end)
    }

    /// After an internal step (`watch`: the impacts announced so far and the communication point
    /// \[s, simulation time\]): the first impact not yet announced whose start lies after the
    /// communication point, if any. Then the state goes back to that start (from the snapshot of
    /// the internal step that holds it, in `starts`) and the early return is returned.
    pub(super) fn return_early(
        &mut self,
        function: &str,
        watch: (usize, f64),
        starts: &[(f64, Snapshot)],
    ) -> Result<Option<Early>, Status> {
        let (announced, from) = watch;
        let sim = self.sim.as_mut().expect("built");
        let times = impact_starts(sim);
        let Some((index, &start)) = times.iter().enumerate().skip(announced).find(|(_, &s)| s > from) else {
            return Ok(None);
        };
        let more = times[index + 1..].iter().any(|&s| s > start);
        let continuation = sim.snapshot();
        let (begin, snapshot) = starts.iter().rev().find(|(t, _)| *t <= start).unwrap_or(&starts[0]);
        sim.restore(snapshot).expect("a snapshot of this model restores");
        if start > *begin {
            if let Err(e) = sim.step_to(start) {
                let at = self.start_time + start;
                return Err(self.error(&format!(
                    "{function}: stepping to the impact's start at t = {at} s for the early return failed: {e}"
                )));
            }
        }
        Ok(Some(Early {
            index,
            continuation,
            more,
        }))
    }
}
