//! What a run with a wall reports instead of a period: its impacts.
//!
//! With a wall, θ(t) crosses zero only inside the impacts (the hanging head touches the face), so
//! a period from zero crossings measures the impact's duration, not a swing. The summary instead
//! reports, from the contact events (the rows of `events.csv`) and the records of θ:
//!
//! * the number of impacts (started; one still going on at the end counts);
//! * the mean interval between the starts of consecutive impacts;
//! * the **coefficient of restitution** of each finished impact, `e = |ω_end| / |ω_start|`: the
//!   angular velocity when the head leaves the wall over the one when it reaches it (for a body
//!   turning about the pivot the normal velocity of the contact point is ω times its lever, so
//!   this is the ratio of the normal velocities), averaged over the impacts; 1 for an impact that
//!   returns all the kinetic energy to the swing. ω is the best-fit rate of the velocity field, so
//!   at the impact's end it carries the elastic vibration the impact leaves in the body: e can
//!   come out a little above 1 for an impact that returns nearly all the energy;
//! * the **rebound angle**: the largest |θ| of the records after the first impact ended and
//!   before the next one started (or the run ended), the swing's amplitude after the impact.

use pendulum_fem_core::simulation::{ContactEvent, ContactEventKind};

/// The impacts of a run, for its summary.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImpactSummary {
    /// Impacts started.
    pub count: usize,
    /// Mean time between the starts of consecutive impacts \[s\] (`None` below two impacts).
    pub mean_interval: Option<f64>,
    /// Mean coefficient of restitution `|ω_end| / |ω_start|` of the finished impacts (`None`
    /// before one has finished).
    pub restitution: Option<f64>,
    /// Largest |θ| between the end of the first impact and the start of the next \[rad\] (`None`
    /// before the first impact has ended).
    pub rebound_angle: Option<f64>,
}

impl ImpactSummary {
    /// The counts, interval and restitution of `events` (in time order, as the stepper lists
    /// them); the rebound angle comes from the records through [`ImpactSummary::observe`].
    pub fn of_events(&mut self, events: &[ContactEvent]) {
        let starts: Vec<&ContactEvent> = events.iter().filter(|e| e.kind == ContactEventKind::Start).collect();
        self.count = starts.len();
        self.mean_interval =
            (starts.len() >= 2).then(|| (starts[starts.len() - 1].time - starts[0].time) / (starts.len() - 1) as f64);
        let ratios: Vec<f64> = events
            .windows(2)
            .filter(|w| w[0].kind == ContactEventKind::Start && w[1].kind == ContactEventKind::End)
            .filter(|w| w[0].omega != 0.0)
            .map(|w| (w[1].omega / w[0].omega).abs())
            .collect();
        self.restitution = (!ratios.is_empty()).then(|| ratios.iter().sum::<f64>() / ratios.len() as f64);
    }

    /// Takes the record θ (\[rad\]) written after the contact events `events`: between the end of
    /// the first impact and the start of the second, it raises the rebound angle.
    pub fn observe(&mut self, events: &[ContactEvent], theta: f64) {
        let first_ended = events.get(1).is_some_and(|e| e.kind == ContactEventKind::End);
        if first_ended && events.len() == 2 {
            self.rebound_angle = Some(self.rebound_angle.map_or(theta.abs(), |r| r.max(theta.abs())));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn event(time: f64, kind: ContactEventKind, omega: f64) -> ContactEvent {
        ContactEvent {
            time,
            kind,
            theta: 0.0,
            omega,
            impulse: 0.0,
            penetration: 0.0,
            force: 0.0,
        }
    }

    #[test]
    fn impacts_give_their_count_mean_interval_and_restitution() {
        use ContactEventKind::{End, Start};
        let events = [
            event(0.24, Start, -1.0),
            event(0.242, End, 0.9),
            event(0.72, Start, -0.9),
            event(0.722, End, 0.72),
            event(1.22, Start, -0.72),
        ];
        let mut s = ImpactSummary::default();
        s.of_events(&events);
        assert_eq!(s.count, 3, "the impact still going on counts");
        assert!((s.mean_interval.unwrap() - 0.49).abs() < 1e-12);
        assert!((s.restitution.unwrap() - 0.85).abs() < 1e-12, "mean of 0.9 and 0.8");
        s.of_events(&events[..1]);
        assert_eq!((s.count, s.mean_interval, s.restitution), (1, None, None));
    }

    #[test]
    fn the_rebound_angle_is_the_largest_angle_between_the_first_and_the_second_impact() {
        use ContactEventKind::{End, Start};
        let events = [
            event(0.24, Start, -1.0),
            event(0.242, End, 1.0),
            event(0.72, Start, -1.0),
        ];
        let mut s = ImpactSummary::default();
        s.observe(&[], 0.35); // the release: before any impact
        s.observe(&events[..1], -0.001); // inside the first
        assert_eq!(s.rebound_angle, None);
        for theta in [0.1, 0.3, 0.34, 0.2] {
            s.observe(&events[..2], theta);
        }
        s.observe(&events, 0.5); // after the second impact started: not the first rebound
        assert_eq!(s.rebound_angle, Some(0.34));
    }
}
