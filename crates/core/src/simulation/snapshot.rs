//! Snapshots of a simulation's complete state, in memory and as bytes.
//!
//! A [`Snapshot`] holds everything that determines the steps after it: the fields `u, v, a` and the
//! time, the hinge multipliers, the counters (steps, Newton iterations, factorisations, cut-backs),
//! the unwrapped θ (the branch of the unwrapping), the `(t, α)` of the previous step (the
//! predictor's `α̇`), the run of equal steps of the clock, the Newton iterations of the last step,
//! the torque's work and the held torque input (terms keep no state of their own), the contact
//! events, the impact in progress and its last sub-step ends (the predictor of a chattering
//! contact), and the
//! solver's reusable factorisation. The factorisation is reused across steps, so the iterates of
//! later steps depend on it bit for bit; the snapshot keeps the *matrix* that was factorised and its
//! frame (not the factor), and restoring factorises that matrix again, which reproduces the factor
//! exactly. Caches that are functions of the state (the rigid-body rates, the mass factorisation of
//! the frames) are recomputed on demand. Hence restore + the same steps is bit for bit the run that
//! never left.
//!
//! **Bytes** ([`Snapshot::to_bytes`], [`Snapshot::from_bytes`]), little-endian:
//!
//! ```text
//! "PFEMSNAP"  magic (8 bytes)
//! u32         format version (SNAPSHOT_VERSION)
//! u64 × 3     model fingerprint ([`Fingerprint`]): FNV-1a of the configuration's values (without
//!             time.end, [output] and the file paths), of the mesh (node coordinates, triangles,
//!             named boundary edges) and of the torque table (times and torques as read)
//! …           the fields in the order of `Snapshot::write_fields`: f64 as IEEE bits, counts as
//!             u64, options as a byte 0/1 and the value, vectors as a u64 length and the values
//! u64         FNV-1a of every byte before it (a damaged or truncated file is refused)
//! ```
//!
//! A snapshot restores only into a model with the same fingerprint ([`Simulation::restore`]); a
//! longer `time.end` or other outputs keep the fingerprint (so a finished run can be continued).
//! The fingerprint covers what determines the dynamics, not where it was read from: the same mesh
//! or torque table reached through a relative or an absolute `mesh.file` / `torque.file` gives the
//! same fingerprint, an edited one another (and the error names the part that differs).
//!
//! **Rolling back within a run.** A step that fails, and an impact's sub-step that is taken again,
//! return to a [`Rollback`] point: a snapshot without the contact events. The event list only grows
//! during a run, so it rolls back by its length; a step then costs nothing in the number of past
//! events (a public snapshot copies them all, as it must). [`Simulation::events_copied`] counts the
//! events copied by snapshots and restores.

mod bytes;

pub use bytes::SNAPSHOT_VERSION;

use std::sync::atomic::Ordering;

use super::events::{ContactPhase, ImpactTrail};
use super::interface::BodySnapshot;
use super::{Clock, ContactEvent, Fingerprint, Simulation};
use crate::error::Error;
use crate::model::State;
use crate::rigid::Unwrap;

/// The complete state of a [`Simulation`] (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    fingerprint: Fingerprint,
    pub(super) state: State,
    lambda: [f64; 2],
    step: usize,
    total_iterations: usize,
    total_factorizations: usize,
    cutbacks: usize,
    torque_work: f64,
    theta: f64,
    clock: Clock,
    last_iterations: usize,
    held_torque: Option<f64>,
    impacts: usize,
    events: Vec<ContactEvent>,
    contact_phase: Option<ContactPhase>,
    impact_trail: ImpactTrail,
    body: BodySnapshot,
}

/// A point to roll back to within a run (see the module doc): the snapshot without the contact
/// events, and the length of the event list.
pub(super) struct Rollback {
    pub(super) snapshot: Snapshot,
    events: usize,
    impact_records: usize,
}

impl Simulation {
    /// The complete state now (see the module doc). Cheap apart from copying the fields and the
    /// contact events: the factorisation is shared, not copied.
    pub fn snapshot(&self) -> Snapshot {
        let events = &self.contact.events;
        self.events_copied.fetch_add(events.len(), Ordering::Relaxed);
        self.snapshot_with(events.clone(), true)
    }

    /// The state now to roll back to within the run: the fields, not the contact events. A
    /// reduced body without a wall keeps no fields: its coordinates are its state, and its fields
    /// are rebuilt from them when read (a roll-back of a bare 10 µs step copies no 130 kB).
    pub(super) fn rollback_point(&self) -> Rollback {
        let fields = self.body.rolls_back_fields(&self.model);
        Rollback {
            snapshot: self.snapshot_with(Vec::new(), fields),
            events: self.contact.events.len(),
            impact_records: self.contact.records.len(),
        }
    }

    /// Returns to `r`: the fields as they were, the contact events since dropped.
    pub(super) fn roll_back(&mut self, r: &Rollback) {
        self.apply_fields(&r.snapshot);
        self.contact.events.truncate(r.events);
        self.contact.records.truncate(r.impact_records);
    }

    /// Contact events copied so far by [`Simulation::snapshot`] and [`Simulation::restore`] (a cost
    /// measure: steps and their roll-backs copy none).
    pub fn events_copied(&self) -> usize {
        self.events_copied.load(Ordering::Relaxed)
    }

    /// The snapshot with `events`, and without the nodal fields unless `fields` (then
    /// [`Simulation::apply_fields`] keeps the current ones and marks them stale).
    fn snapshot_with(&self, events: Vec<ContactEvent>, fields: bool) -> Snapshot {
        let now = &self.now;
        let state = match fields {
            true => now.state.clone(),
            false => State {
                t: now.state.t,
                u: Vec::new(),
                v: Vec::new(),
                a: Vec::new(),
            },
        };
        Snapshot {
            fingerprint: self.model.fingerprint,
            state,
            lambda: now.lambda,
            step: self.step,
            total_iterations: self.total_iterations,
            total_factorizations: self.total_factorizations,
            cutbacks: self.cutbacks,
            torque_work: now.torque_work,
            theta: now.theta,
            clock: self.clock,
            last_iterations: self.last_iterations,
            held_torque: now.held_torque,
            impacts: self.contact.count,
            events,
            contact_phase: self.contact.phase,
            impact_trail: self.contact.trail.clone(),
            body: self.body.save(),
        }
    }

    /// Returns to the state of `snapshot`: the following steps are bit for bit those that followed
    /// when it was taken. A snapshot of another model (another fingerprint: configuration or mesh)
    /// or of fields of another size is an error, and nothing is changed then.
    pub fn restore(&mut self, snapshot: &Snapshot) -> Result<(), Error> {
        if let Some(parts) = snapshot
            .fingerprint
            .differences(&self.model.fingerprint, &self.model.config)
        {
            return Err(Error::Input(format!(
                "snapshot: made for another model: {parts} (fingerprint {}; this model's {}): restore a snapshot only into the configuration and mesh it was made with \
                 (time.end, [output] and the paths of mesh.file and torque.file may differ, not the files' contents)",
                snapshot.fingerprint, self.model.fingerprint
            )));
        }
        let n = self.now.state.u.len();
        let s = &snapshot.state;
        let trail = snapshot.impact_trail.earlier.iter().map(|(_, u)| u.len());
        if let Some(m) = [s.u.len(), s.v.len(), s.a.len()]
            .into_iter()
            .chain(trail)
            .find(|&m| m != n)
        {
            return Err(Error::Input(format!(
                "snapshot: fields of {m} values for a mesh of {n} degrees of freedom"
            )));
        }
        self.apply_fields(snapshot);
        self.events_copied.fetch_add(snapshot.events.len(), Ordering::Relaxed);
        self.contact.events = snapshot.events.clone();
        // the records belong to the steps the restore undoes or skips
        self.contact.records.clear();
        Ok(())
    }

    /// Sets every part of the state from `s` but the contact events (no checks; see
    /// [`Simulation::restore`]).
    fn apply_fields(&mut self, s: &Snapshot) {
        let now = &mut self.now;
        match s.state.u.is_empty() && !now.state.u.is_empty() {
            // a roll-back point without fields (see [`Simulation::rollback_point`])
            true => now.state.t = s.state.t,
            false => now.state = s.state.clone(),
        }
        now.lambda = s.lambda;
        now.torque_work = s.torque_work;
        now.theta = s.theta;
        now.unwrap = Unwrap::starting_at(s.theta);
        now.held_torque = s.held_torque;
        now.forget_measures();
        self.step = s.step;
        self.total_iterations = s.total_iterations;
        self.total_factorizations = s.total_factorizations;
        self.cutbacks = s.cutbacks;
        self.clock = s.clock;
        self.last_iterations = s.last_iterations;
        self.contact.count = s.impacts;
        self.contact.phase = s.contact_phase;
        self.contact.trail = s.impact_trail.clone();
        self.body.restore(&self.model, &s.body);
    }
}

impl Snapshot {
    /// Step number of the snapshot.
    pub fn step(&self) -> usize {
        self.step
    }

    /// Time of the snapshot \[s\].
    pub fn time(&self) -> f64 {
        self.state.t
    }

    /// The model fingerprint it was made with (see [`crate::model::Model::fingerprint`]).
    pub fn fingerprint(&self) -> Fingerprint {
        self.fingerprint
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::fingerprint::tests::table_config;

    #[test]
    fn a_snapshot_restores_through_another_path_to_the_same_table_but_not_after_the_table_is_edited() {
        let dir = std::env::temp_dir().join(format!("pendulum-fem-fingerprint-{}", std::process::id()));
        let table = "time_s,torque_Nm\n0,0\n0.02,0.3\n1,0.1\n";
        let mut sims = Vec::new();
        for (name, text) in [("a", table), ("b", table), ("edited", &table.replace("0.3", "0.31"))] {
            std::fs::create_dir_all(dir.join(name)).unwrap();
            let file = dir.join(name).join("t.csv");
            std::fs::write(&file, text).unwrap();
            let cfg = table_config(file.to_str().unwrap());
            sims.push(Simulation::from_config(&cfg, crate::mesh::generate(&cfg).unwrap()).unwrap());
        }
        let _ = std::fs::remove_dir_all(&dir);
        let [a, b, edited] = &mut sims[..] else { unreachable!() };
        a.step(0.01).unwrap();
        let snap = Snapshot::from_bytes(&a.snapshot().to_bytes(), "mem").unwrap();
        b.restore(&snap).unwrap();
        a.step(0.01).unwrap();
        b.step(0.01).unwrap();
        assert_eq!(
            a.snapshot(),
            b.snapshot(),
            "the same table in another folder: the same run"
        );
        let before = edited.snapshot();
        let msg = edited.restore(&snap).unwrap_err().to_string();
        assert!(
            msg.contains("another model")
                && msg.contains("the torque table (times and torques of torque.file = ")
                && msg.contains("edited"),
            "{msg}"
        );
        assert_eq!(edited.snapshot(), before, "a refused snapshot changes nothing");
    }
}
