//! Records to rows: the values of a [`StepRecord`] in `results.csv`'s column order and back (for a
//! restart), and the rows of `events.csv`.

use pendulum_fem_core::post::unsigned_zero;
use pendulum_fem_core::simulation::{ContactEvent, ContactRecord, StepRecord};
use pendulum_fem_core::Error;

/// The values of a record in CSV column order, a negative zero as `0`
/// ([`pendulum_fem_core::post::unsigned_zero`]).
/// The columns are [`StepRecord::HEADER`]'s, then [`StepRecord::CONTACT_HEADER`]'s for a model
/// with a wall.
pub fn csv_values(r: &StepRecord) -> Vec<f64> {
    let mut v = vec![
        r.time,
        r.theta,
        r.omega,
        r.alpha,
        r.kinetic,
        r.strain,
        r.gravity,
        r.total,
        r.hinge_force[0],
        r.hinge_force[1],
        r.von_mises_max,
        r.newton_iterations as f64,
        r.torque,
        r.torque_work,
        r.angular_momentum,
    ];
    if let Some(c) = &r.contact {
        v.extend([c.gap, c.force, c.energy, c.impacts as f64]);
    }
    v.into_iter().map(unsigned_zero).collect()
}

/// Header of `events.csv`.
pub const EVENTS_HEADER: &str = "time_s,event,theta_rad,omega_rad_s,impulse_N_s,max_penetration_m,max_force_N";

/// Writes `events.csv` (every contact event so far; replaced atomically, so that a stopped or
/// restarted run leaves it whole).
pub(crate) fn write_events(dir: &std::path::Path, events: &[ContactEvent]) -> Result<(), Error> {
    let mut text = format!("{EVENTS_HEADER}\n");
    for e in events {
        let [time, theta, omega, impulse, penetration, force] =
            [e.time, e.theta, e.omega, e.impulse, e.penetration, e.force].map(unsigned_zero);
        text.push_str(&format!(
            "{time},{},{theta},{omega},{impulse},{penetration},{force}\n",
            e.kind.name()
        ));
    }
    crate::files::write_atomically(&dir.join("events.csv"), |w| w.write_all(text.as_bytes()))
}

/// The record of a `results.csv` row (in [`csv_values`] order) of step `step`.
pub fn record_of_row(step: usize, v: &[f64]) -> StepRecord {
    StepRecord {
        step,
        time: v[0],
        theta: v[1],
        omega: v[2],
        alpha: v[3],
        kinetic: v[4],
        strain: v[5],
        gravity: v[6],
        total: v[7],
        hinge_force: [v[8], v[9]],
        von_mises_max: v[10],
        newton_iterations: v[11] as usize,
        torque: v[12],
        torque_work: v[13],
        angular_momentum: v[14],
        contact: (v.len() >= 19).then(|| ContactRecord {
            gap: v[15],
            force: v[16],
            energy: v[17],
            impacts: v[18] as usize,
        }),
    }
}
