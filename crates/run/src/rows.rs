//! Records to rows and back: the values of a [`StepRecord`] in `results.csv`'s column order, the
//! records of a table of those columns (a restart's rows before its checkpoint, a test's look at
//! a run's folder), and the rows of `events.csv` both ways.

use std::path::Path;

use pendulum_fem_core::post::unsigned_zero;
use pendulum_fem_core::simulation::{ContactEvent, ContactEventKind, ContactRecord, StepRecord};
use pendulum_fem_core::store::Table;
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

/// The row of `events.csv` of a contact event (without the line break), a negative zero as `0`.
pub fn event_row(e: &ContactEvent) -> String {
    let [time, theta, omega, impulse, penetration, force] =
        [e.time, e.theta, e.omega, e.impulse, e.penetration, e.force].map(unsigned_zero);
    format!(
        "{time},{},{theta},{omega},{impulse},{penetration},{force}",
        event_name(e.kind)
    )
}

/// Reads the contact events of an `events.csv` (this program's header and rows, [`event_row`]);
/// errors name the file and the line.
pub fn read_events(path: &Path) -> Result<Vec<ContactEvent>, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let source = path.display();
    let mut lines = text.lines().enumerate();
    let header = lines.next().map_or("", |(_, l)| l);
    if header != EVENTS_HEADER {
        return Err(Error::Input(format!(
            "{source}:1: the header `{header}` is not this program's `{EVENTS_HEADER}`"
        )));
    }
    let mut events = Vec::new();
    for (i, line) in lines.filter(|(_, l)| !l.trim().is_empty()) {
        let bad = |what: &str| Error::Input(format!("{source}:{}: {what} (in `{line}`)", i + 1));
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let [time, kind, theta, omega, impulse, penetration, force] = cells[..] else {
            return Err(bad(&format!("{} values, the header has 7 columns", cells.len())));
        };
        let kind = match kind {
            "impact_start" => ContactEventKind::Start,
            "impact_end" => ContactEventKind::End,
            other => return Err(bad(&format!("`{other}` is not an event (impact_start, impact_end)"))),
        };
        let number = |cell: &str| {
            cell.parse::<f64>()
                .map_err(|_| bad(&format!("`{cell}` is not a number")))
        };
        events.push(ContactEvent {
            time: number(time)?,
            kind,
            theta: number(theta)?,
            omega: number(omega)?,
            impulse: number(impulse)?,
            penetration: number(penetration)?,
            force: number(force)?,
        });
    }
    Ok(events)
}

/// The records of a table of `results.csv`'s (or `impacts.csv`'s) columns, the step of each its
/// row's index; a table with other columns is an error naming `source`.
pub fn records_of_table(table: &Table, source: &str) -> Result<Vec<StepRecord>, Error> {
    let names = table.names.join(",");
    let expected = header(table.names.len() > COLUMNS.len());
    if names != expected {
        return Err(Error::Input(format!(
            "{source}: the columns `{names}` are not this program's `{expected}`"
        )));
    }
    Ok(table
        .rows
        .iter()
        .enumerate()
        .map(|(i, row)| record_of_row(i, row))
        .collect())
}

/// Reads the records of a `results.csv` or `impacts.csv` ([`records_of_table`]); errors name the
/// file and the line.
pub fn read_records(path: &Path) -> Result<Vec<StepRecord>, Error> {
    records_of_table(&Table::read(path)?, &path.display().to_string())
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
    fn events_csv_reads_back_to_the_events_written_and_bad_rows_name_their_line() {
        let dir = std::env::temp_dir().join(format!("pendulum-fem-events-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("events.csv");
        let events = [
            ContactEvent {
                time: 0.2401,
                kind: ContactEventKind::Start,
                theta: 1e-3,
                omega: -1.25,
                impulse: 0.0,
                penetration: 0.0,
                force: 0.0,
            },
            ContactEvent {
                time: 0.2423,
                kind: ContactEventKind::End,
                theta: 2e-4,
                omega: 1.249,
                impulse: 0.03125,
                penetration: 1.5e-6,
                force: 712.5,
            },
        ];
        let mut text = format!("{EVENTS_HEADER}\n");
        events.iter().for_each(|e| text.push_str(&(event_row(e) + "\n")));
        std::fs::write(&path, &text).unwrap();
        assert_eq!(read_events(&path).unwrap(), events);
        std::fs::write(&path, text.replace("impact_end", "impact_middle")).unwrap();
        let e = read_events(&path).unwrap_err().to_string();
        assert!(e.contains("events.csv:3: `impact_middle` is not an event"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn records_read_back_from_a_table_of_this_programs_columns_only() {
        let r = record(true);
        let row: Vec<String> = csv_values(&r).iter().map(f64::to_string).collect();
        let text = format!("{}\n{}\n{}\n", header(true), row.join(","), row.join(","));
        let records = records_of_table(&Table::parse(&text, "x.csv").unwrap(), "x.csv").unwrap();
        assert_eq!(records.iter().map(|r| r.step).collect::<Vec<_>>(), [0, 1]);
        assert_eq!(records[1], StepRecord { step: 1, ..r });
        let other = Table::parse("time_s,theta_rad\n0,1\n", "y.csv").unwrap();
        let e = records_of_table(&other, "y.csv").unwrap_err().to_string();
        assert!(
            e.contains("y.csv: the columns `time_s,theta_rad` are not this program's"),
            "{e}"
        );
    }

    #[test]
    fn a_nan_in_any_column_of_results_csv_but_the_time_and_the_counts_is_a_record_refused() {
        // the time is the clock's, the counts are integers: every other column is a result
        let unchecked = ["time_s", "newton_iterations", "impacts"];
        record(true).check_finite().unwrap();
        let mut checked = 0;
        for (k, name) in header(true).split(',').enumerate() {
            let mut r = record(true);
            match COLUMNS.get(k) {
                Some(column) => (column.set)(&mut r, f64::NAN),
                None => (CONTACT_COLUMNS[k - COLUMNS.len()].set)(r.contact.as_mut().unwrap(), f64::NAN),
            }
            if unchecked.contains(&name) {
                continue;
            }
            assert!(r.first_non_finite().is_some(), "a NaN in {name} passes");
            assert!(r.check_finite().is_err(), "{name}");
            checked += 1;
        }
        assert_eq!(checked, 16);
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
