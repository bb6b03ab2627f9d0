//! Records to rows: the values of a [`StepRecord`] in `results.csv`'s column order and back (for a
//! restart), and the rows of `events.csv`.

use pendulum_fem_core::post::unsigned_zero;
use pendulum_fem_core::simulation::{ContactEvent, ContactEventKind, ContactRecord, StepRecord};
use pendulum_fem_core::Error;

/// A column of `results.csv`: its name, its value in a record, and the record field it fills
/// when a row is read back (a restart).
struct Column<R> {
    name: &'static str,
    get: fn(&R) -> f64,
    set: fn(&mut R, f64),
}

/// The columns of `results.csv`, in order: the one definition of their names and order.
const COLUMNS: [Column<StepRecord>; 15] = [
    Column {
        name: "time_s",
        get: |r| r.time,
        set: |r, v| r.time = v,
    },
    Column {
        name: "theta_rad",
        get: |r| r.theta,
        set: |r, v| r.theta = v,
    },
    Column {
        name: "omega_rad_s",
        get: |r| r.omega,
        set: |r, v| r.omega = v,
    },
    Column {
        name: "alpha_rad_s2",
        get: |r| r.alpha,
        set: |r, v| r.alpha = v,
    },
    Column {
        name: "kinetic_J",
        get: |r| r.kinetic,
        set: |r, v| r.kinetic = v,
    },
    Column {
        name: "strain_J",
        get: |r| r.strain,
        set: |r, v| r.strain = v,
    },
    Column {
        name: "gravity_J",
        get: |r| r.gravity,
        set: |r, v| r.gravity = v,
    },
    Column {
        name: "total_J",
        get: |r| r.total,
        set: |r, v| r.total = v,
    },
    Column {
        name: "hinge_fx_N",
        get: |r| r.hinge_force[0],
        set: |r, v| r.hinge_force[0] = v,
    },
    Column {
        name: "hinge_fy_N",
        get: |r| r.hinge_force[1],
        set: |r, v| r.hinge_force[1] = v,
    },
    Column {
        name: "von_mises_max_Pa",
        get: |r| r.von_mises_max,
        set: |r, v| r.von_mises_max = v,
    },
    Column {
        name: "newton_iterations",
        get: |r| r.newton_iterations as f64,
        set: |r, v| r.newton_iterations = v as usize,
    },
    Column {
        name: "torque_Nm",
        get: |r| r.torque,
        set: |r, v| r.torque = v,
    },
    Column {
        name: "torque_work_J",
        get: |r| r.torque_work,
        set: |r, v| r.torque_work = v,
    },
    Column {
        name: "angular_momentum_kg_m2_s",
        get: |r| r.angular_momentum,
        set: |r, v| r.angular_momentum = v,
    },
];

/// The columns a model with a wall adds after [`COLUMNS`].
const CONTACT_COLUMNS: [Column<ContactRecord>; 4] = [
    Column {
        name: "gap_m",
        get: |c| c.gap,
        set: |c, v| c.gap = v,
    },
    Column {
        name: "contact_force_N",
        get: |c| c.force,
        set: |c, v| c.force = v,
    },
    Column {
        name: "contact_J",
        get: |c| c.energy,
        set: |c, v| c.energy = v,
    },
    Column {
        name: "impacts",
        get: |c| c.impacts as f64,
        set: |c, v| c.impacts = v as usize,
    },
];

/// The header of `results.csv` (and `impacts.csv`) of a run with (`contact`) or without a wall.
pub fn header(contact: bool) -> String {
    let contact_columns: &[Column<ContactRecord>] = if contact { &CONTACT_COLUMNS } else { &[] };
    let names: Vec<&str> = COLUMNS
        .iter()
        .map(|c| c.name)
        .chain(contact_columns.iter().map(|c| c.name))
        .collect();
    names.join(",")
}

/// The values of a record in the order of [`header`] (the contact columns when the record has
/// them), a negative zero as `0` ([`pendulum_fem_core::post::unsigned_zero`]).
pub fn csv_values(r: &StepRecord) -> Vec<f64> {
    let contact = r
        .contact
        .iter()
        .flat_map(|c| CONTACT_COLUMNS.iter().map(move |col| (col.get)(c)));
    COLUMNS
        .iter()
        .map(|col| (col.get)(r))
        .chain(contact)
        .map(unsigned_zero)
        .collect()
}

/// The name of an event kind in `events.csv` (and the Python package's event rows).
pub fn event_name(kind: ContactEventKind) -> &'static str {
    match kind {
        ContactEventKind::Start => "impact_start",
        ContactEventKind::End => "impact_end",
    }
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
            event_name(e.kind)
        ));
    }
    pendulum_fem_core::store::write_atomically(&dir.join("events.csv"), |w| w.write_all(text.as_bytes()))
}

/// The record of a `results.csv` row (in [`csv_values`] order) of step `step`.
pub fn record_of_row(step: usize, v: &[f64]) -> StepRecord {
    let mut r = StepRecord {
        step,
        ..Default::default()
    };
    for (col, &x) in COLUMNS.iter().zip(v) {
        (col.set)(&mut r, x);
    }
    if v.len() >= COLUMNS.len() + CONTACT_COLUMNS.len() {
        let mut c = ContactRecord::default();
        for (col, &x) in CONTACT_COLUMNS.iter().zip(&v[COLUMNS.len()..]) {
            (col.set)(&mut c, x);
        }
        r.contact = Some(c);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record whose every field holds a different value (integers where the field is a count).
    fn record(contact: bool) -> StepRecord {
        StepRecord {
            step: 7,
            time: 0.07,
            theta: 0.3,
            omega: -1.5,
            alpha: 2.5,
            kinetic: 0.25,
            strain: 1e-6,
            gravity: -3.0,
            total: -2.75,
            hinge_force: [1.25, -7.5],
            von_mises_max: 4.5e6,
            newton_iterations: 5,
            torque: 0.5,
            torque_work: 0.125,
            angular_momentum: 0.0625,
            contact: contact.then_some(ContactRecord {
                gap: -1e-5,
                force: 700.0,
                energy: 3e-3,
                impacts: 2,
            }),
        }
    }

    #[test]
    fn a_row_reads_back_to_the_record_it_was_written_from_with_and_without_a_wall() {
        for contact in [false, true] {
            let r = record(contact);
            let values = csv_values(&r);
            assert_eq!(values.len(), header(contact).split(',').count());
            assert_eq!(record_of_row(r.step, &values), r);
        }
    }

    #[test]
    fn the_header_names_the_columns_in_the_order_of_the_values() {
        let names: Vec<String> = header(true).split(',').map(str::to_string).collect();
        let values = csv_values(&record(true));
        let at = |name: &str| values[names.iter().position(|n| n == name).unwrap()];
        assert_eq!((at("time_s"), at("total_J"), at("hinge_fy_N")), (0.07, -2.75, -7.5));
        assert_eq!(
            (at("newton_iterations"), at("contact_force_N"), at("impacts")),
            (5.0, 700.0, 2.0)
        );
        assert_eq!(names.last().map(String::as_str), Some("impacts"));
    }
}
