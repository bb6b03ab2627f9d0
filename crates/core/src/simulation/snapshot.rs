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

use std::sync::atomic::Ordering;
use std::sync::Arc;

use super::impact::{ContactPhase, ImpactTrail};
use super::{Clock, ContactEvent, ContactEventKind, Simulation};
use crate::config::Config;
use crate::newmark::State;
use crate::newton::FactorState;
use crate::post::Unwrap;
use crate::terms::torque::TorqueTable;
use crate::{Error, Mesh};

/// Version of the byte format of [`Snapshot::to_bytes`] (3: the fingerprint in three parts, without
/// file paths; 4: the impact's last sub-step ends).
pub const SNAPSHOT_VERSION: u32 = 4;

const MAGIC: &[u8; 8] = b"PFEMSNAP";

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
    previous_alpha: Option<(f64, f64)>,
    clock: Clock,
    last_iterations: usize,
    held_torque: Option<f64>,
    impacts: usize,
    events: Vec<ContactEvent>,
    contact_phase: Option<ContactPhase>,
    impact_trail: ImpactTrail,
    factor: Option<Arc<FactorState>>,
}

/// 64-bit FNV-1a.
#[derive(Clone, Copy, Debug)]
struct Fnv(u64);

impl Fnv {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;

    fn new() -> Self {
        Self(Self::OFFSET)
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(Self::PRIME);
        }
    }
}

/// FNV-1a of `bytes`.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h = Fnv::new();
    h.write(bytes);
    h.0
}

/// What a model is made of, part by part, as FNV-1a hashes: what determines its dynamics, not the
/// names of the files it was read from. A [`Snapshot`] restores only into a model with an equal
/// fingerprint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fingerprint {
    /// The configuration as JSON without `time.end` and `[output]` (they do not change the state of
    /// a step) and without the file paths `mesh.file` and `torque.file` (their contents count, in
    /// `mesh` and `torque_table`); then the settings of bodies not described by the configuration.
    pub config: u64,
    /// The mesh of every body: each node coordinate (IEEE bits), each triangle's node numbers,
    /// each boundary edge's nodes and name.
    pub mesh: u64,
    /// The torque table (`torque.profile = "table"`) as read: its times and torques (IEEE bits);
    /// the hash of no bytes without a table.
    pub torque_table: u64,
}

/// The fingerprint of a model of `config` on `mesh` (every body's) with the torque table `table`
/// read from `torque.file` (see [`Fingerprint`]).
pub fn fingerprint(config: &Config, mesh: &Mesh, table: Option<&TorqueTable>) -> Fingerprint {
    let mut json = serde_json::to_value(config).unwrap_or(serde_json::Value::Null);
    if let Some(obj) = json.as_object_mut() {
        obj.remove("output");
        for (section, key) in [("time", "end"), ("mesh", "file"), ("torque", "file")] {
            if let Some(section) = obj.get_mut(section).and_then(|t| t.as_object_mut()) {
                section.remove(key);
            }
        }
    }
    let mut m = Fnv::new();
    for p in &mesh.nodes {
        m.write(&p[0].to_bits().to_le_bytes());
        m.write(&p[1].to_bits().to_le_bytes());
    }
    for t in &mesh.triangles {
        for &n in t {
            m.write(&(n as u64).to_le_bytes());
        }
    }
    for e in &mesh.boundary_edges {
        for &n in &e.nodes {
            m.write(&(n as u64).to_le_bytes());
        }
        let name = mesh.boundary_names.get(e.name).map_or("", String::as_str);
        m.write(&(name.len() as u64).to_le_bytes());
        m.write(name.as_bytes());
    }
    let mut t = Fnv::new();
    if let Some(table) = table {
        t.write(&(table.times.len() as u64).to_le_bytes());
        for x in table.times.iter().chain(&table.torques) {
            t.write(&x.to_bits().to_le_bytes());
        }
    }
    Fingerprint {
        config: fnv1a(json.to_string().as_bytes()),
        mesh: m.0,
        torque_table: t.0,
    }
}

impl Fingerprint {
    /// Mixes `bytes` (the settings of a further body) into the configuration part.
    pub fn add_settings(&mut self, bytes: &[u8]) {
        self.config = fnv1a(&[self.config.to_le_bytes().as_slice(), bytes].concat());
    }

    /// `None` when equal; else which parts of `self` (a snapshot's) differ from `model`'s, as a
    /// clause for an error message ("the torque table (times and torques of torque.file = t.csv)
    /// differs"; `config` is the model's, for the names of its files).
    pub fn differences(&self, model: &Fingerprint, config: &Config) -> Option<String> {
        let mut parts = Vec::new();
        if self.config != model.config {
            parts.push("the configuration's values".to_string());
        }
        if self.mesh != model.mesh {
            parts.push(match &config.mesh.file {
                Some(f) => format!("the mesh (nodes, triangles, boundaries of mesh.file = {})", f.display()),
                None => "the mesh (nodes, triangles, boundaries)".to_string(),
            });
        }
        if self.torque_table != model.torque_table {
            let table = config.torque.profile == crate::config::TorqueProfile::Table;
            parts.push(match config.torque.file.as_ref().filter(|_| table) {
                Some(f) => format!("the torque table (times and torques of torque.file = {})", f.display()),
                None => "the torque table (this model has none)".to_string(),
            });
        }
        match parts.as_slice() {
            [] => None,
            [one] => Some(format!("{one} differs")),
            [first @ .., last] => Some(format!("{} and {last} differ", first.join(", "))),
        }
    }
}

impl std::fmt::Display for Fingerprint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:016x}-{:016x}-{:016x}", self.config, self.mesh, self.torque_table)
    }
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
        self.events_copied.fetch_add(self.events.len(), Ordering::Relaxed);
        self.snapshot_with(self.events.clone())
    }

    /// The state now to roll back to within the run: the fields, not the contact events.
    pub(super) fn rollback_point(&self) -> Rollback {
        Rollback {
            snapshot: self.snapshot_with(Vec::new()),
            events: self.events.len(),
            impact_records: self.impact_records.len(),
        }
    }

    /// Returns to `r`: the fields as they were, the contact events since dropped.
    pub(super) fn roll_back(&mut self, r: &Rollback) {
        self.apply_fields(&r.snapshot);
        self.events.truncate(r.events);
        self.impact_records.truncate(r.impact_records);
    }

    /// Contact events copied so far by [`Simulation::snapshot`] and [`Simulation::restore`] (a cost
    /// measure: steps and their roll-backs copy none).
    pub fn events_copied(&self) -> usize {
        self.events_copied.load(Ordering::Relaxed)
    }

    fn snapshot_with(&self, events: Vec<ContactEvent>) -> Snapshot {
        Snapshot {
            fingerprint: self.model.fingerprint,
            state: self.state.clone(),
            lambda: self.lambda,
            step: self.step,
            total_iterations: self.total_iterations,
            total_factorizations: self.total_factorizations,
            cutbacks: self.cutbacks,
            torque_work: self.torque_work,
            theta: self.theta,
            previous_alpha: self.previous_alpha,
            clock: self.clock,
            last_iterations: self.last_iterations,
            held_torque: self.held_torque,
            impacts: self.impacts,
            events,
            contact_phase: self.contact_phase,
            impact_trail: self.impact_trail.clone(),
            factor: self.solver.factor_state(),
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
        let n = self.state.u.len();
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
        self.events = snapshot.events.clone();
        // the records belong to the steps the restore undoes or skips
        self.impact_records.clear();
        Ok(())
    }

    /// Sets every part of the state from `s` but the contact events (no checks; see
    /// [`Simulation::restore`]).
    fn apply_fields(&mut self, s: &Snapshot) {
        self.state = s.state.clone();
        self.lambda = s.lambda;
        self.step = s.step;
        self.total_iterations = s.total_iterations;
        self.total_factorizations = s.total_factorizations;
        self.cutbacks = s.cutbacks;
        self.torque_work = s.torque_work;
        self.theta = s.theta;
        self.unwrap = Unwrap::starting_at(s.theta);
        self.previous_alpha = s.previous_alpha;
        self.clock = s.clock;
        self.last_iterations = s.last_iterations;
        self.apply_torque_input(s.held_torque);
        self.impacts = s.impacts;
        self.contact_phase = s.contact_phase;
        self.impact_trail = s.impact_trail.clone();
        self.rates = None;
        // The matrix was factorised before with this symbolic analysis; should that fail now, the
        // next step factorises afresh.
        if self
            .solver
            .restore_factor(&self.model.pattern, s.factor.clone())
            .is_err()
        {
            let _ = self.solver.restore_factor(&self.model.pattern, None);
        }
    }
}

struct Writer(Vec<u8>);

impl Writer {
    fn u8(&mut self, x: u8) {
        self.0.push(x);
    }
    fn u32(&mut self, x: u32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn usize(&mut self, x: usize) {
        self.u64(x as u64);
    }
    fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }
    fn opt_f64(&mut self, x: Option<f64>) {
        match x {
            Some(v) => {
                self.u8(1);
                self.f64(v);
            }
            None => self.u8(0),
        }
    }
    fn vec(&mut self, v: &[f64]) {
        self.usize(v.len());
        v.iter().for_each(|&x| self.f64(x));
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
    source: &'a str,
}

impl Reader<'_> {
    fn take(&mut self, n: usize, what: &str) -> Result<&[u8], Error> {
        if self.bytes.len() - self.pos < n {
            return Err(Error::Input(format!(
                "{}: truncated snapshot: {what} at byte {} needs {n} bytes, {} remain",
                self.source,
                self.pos,
                self.bytes.len() - self.pos
            )));
        }
        let s = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }
    fn u8(&mut self, what: &str) -> Result<u8, Error> {
        Ok(self.take(1, what)?[0])
    }
    fn u64(&mut self, what: &str) -> Result<u64, Error> {
        Ok(u64::from_le_bytes(self.take(8, what)?.try_into().expect("8 bytes")))
    }
    fn usize(&mut self, what: &str) -> Result<usize, Error> {
        let at = self.pos;
        let x = self.u64(what)?;
        usize::try_from(x).map_err(|_| Error::Input(format!("{}: {what} at byte {at}: {x} is too large", self.source)))
    }
    fn f64(&mut self, what: &str) -> Result<f64, Error> {
        Ok(f64::from_bits(self.u64(what)?))
    }
    fn flag(&mut self, what: &str) -> Result<bool, Error> {
        let at = self.pos;
        match self.u8(what)? {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(Error::Input(format!(
                "{}: {what} at byte {at}: option flag {b}, allowed 0 or 1",
                self.source
            ))),
        }
    }
    fn opt_f64(&mut self, what: &str) -> Result<Option<f64>, Error> {
        Ok(if self.flag(what)? { Some(self.f64(what)?) } else { None })
    }
    fn vec(&mut self, what: &str) -> Result<Vec<f64>, Error> {
        let n = self.usize(what)?;
        if n > (self.bytes.len() - self.pos) / 8 {
            return Err(Error::Input(format!(
                "{}: truncated snapshot: {what} of {n} values at byte {}",
                self.source, self.pos
            )));
        }
        (0..n).map(|_| self.f64(what)).collect()
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

    /// The model fingerprint it was made with (see [`crate::simulation::Model::fingerprint`]).
    pub fn fingerprint(&self) -> Fingerprint {
        self.fingerprint
    }

    /// The snapshot as bytes (format in the module doc).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = Writer(Vec::new());
        w.0.extend_from_slice(MAGIC);
        w.u32(SNAPSHOT_VERSION);
        w.u64(self.fingerprint.config);
        w.u64(self.fingerprint.mesh);
        w.u64(self.fingerprint.torque_table);
        w.f64(self.state.t);
        w.vec(&self.state.u);
        w.vec(&self.state.v);
        w.vec(&self.state.a);
        w.f64(self.lambda[0]);
        w.f64(self.lambda[1]);
        w.usize(self.step);
        w.usize(self.total_iterations);
        w.usize(self.total_factorizations);
        w.usize(self.cutbacks);
        w.f64(self.torque_work);
        w.f64(self.theta);
        match self.previous_alpha {
            Some((t, a)) => {
                w.u8(1);
                w.f64(t);
                w.f64(a);
            }
            None => w.u8(0),
        }
        w.f64(self.clock.base);
        w.f64(self.clock.dt);
        w.u64(self.clock.count);
        w.usize(self.last_iterations);
        w.opt_f64(self.held_torque);
        w.usize(self.impacts);
        w.usize(self.events.len());
        for e in &self.events {
            w.f64(e.time);
            w.u8(u8::from(e.kind == ContactEventKind::End));
            w.f64(e.theta);
            w.f64(e.omega);
            w.f64(e.impulse);
            w.f64(e.penetration);
            w.f64(e.force);
        }
        match self.contact_phase {
            Some(p) => {
                w.u8(1);
                w.f64(p.substep);
                w.u8(u8::from(p.resolved));
                w.f64(p.first_substep);
                w.opt_f64(p.separated);
                w.f64(p.touch);
                w.u8(u8::from(p.penetrated));
                w.f64(p.impulse);
                w.f64(p.penetration);
                w.f64(p.force);
            }
            None => w.u8(0),
        }
        w.usize(self.impact_trail.earlier.len());
        for (t, u) in &self.impact_trail.earlier {
            w.f64(*t);
            w.vec(u);
        }
        w.f64(self.impact_trail.end);
        match &self.factor {
            Some(f) => {
                w.u8(1);
                w.f64(f.frame.0);
                w.f64(f.frame.1);
                w.vec(&f.values);
            }
            None => w.u8(0),
        }
        let sum = fnv1a(&w.0);
        w.u64(sum);
        w.0
    }

    /// Reads bytes written by [`Snapshot::to_bytes`]; `source` names them in errors (a file name).
    /// A wrong magic, another format version, a damaged or truncated file are errors.
    pub fn from_bytes(bytes: &[u8], source: &str) -> Result<Self, Error> {
        if bytes.len() < MAGIC.len() + 4 + 8 || &bytes[..MAGIC.len()] != MAGIC {
            return Err(Error::Input(format!(
                "{source}: not a pendulum-fem snapshot (it does not start with \"PFEMSNAP\")"
            )));
        }
        let version = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
        if version != SNAPSHOT_VERSION {
            return Err(Error::Input(format!(
                "{source}: snapshot format version {version}; this program reads version {SNAPSHOT_VERSION}"
            )));
        }
        let body = &bytes[..bytes.len() - 8];
        let stored = u64::from_le_bytes(bytes[bytes.len() - 8..].try_into().expect("8 bytes"));
        if fnv1a(body) != stored {
            return Err(Error::Input(format!(
                "{source}: damaged snapshot (its checksum does not match its {} bytes)",
                bytes.len()
            )));
        }
        let mut r = Reader {
            bytes: body,
            pos: 12,
            source,
        };
        let fingerprint = Fingerprint {
            config: r.u64("fingerprint")?,
            mesh: r.u64("fingerprint")?,
            torque_table: r.u64("fingerprint")?,
        };
        let t = r.f64("time")?;
        let u = r.vec("u")?;
        let v = r.vec("v")?;
        let a = r.vec("a")?;
        let lambda = [r.f64("lambda")?, r.f64("lambda")?];
        let step = r.usize("step")?;
        let total_iterations = r.usize("iterations")?;
        let total_factorizations = r.usize("factorizations")?;
        let cutbacks = r.usize("cutbacks")?;
        let torque_work = r.f64("torque work")?;
        let theta = r.f64("theta")?;
        let previous_alpha = if r.flag("previous alpha")? {
            Some((r.f64("previous alpha")?, r.f64("previous alpha")?))
        } else {
            None
        };
        let clock = Clock {
            base: r.f64("clock")?,
            dt: r.f64("clock")?,
            count: r.u64("clock")?,
        };
        let last_iterations = r.usize("last iterations")?;
        let held_torque = r.opt_f64("held torque")?;
        let impacts = r.usize("impacts")?;
        let count = r.usize("events")?;
        if count > body.len() {
            return Err(Error::Input(format!(
                "{source}: {count} contact events in a snapshot of {} bytes",
                body.len()
            )));
        }
        let mut events = Vec::with_capacity(count);
        for _ in 0..count {
            events.push(ContactEvent {
                time: r.f64("event")?,
                kind: if r.flag("event")? {
                    ContactEventKind::End
                } else {
                    ContactEventKind::Start
                },
                theta: r.f64("event")?,
                omega: r.f64("event")?,
                impulse: r.f64("event")?,
                penetration: r.f64("event")?,
                force: r.f64("event")?,
            });
        }
        let contact_phase = if r.flag("contact")? {
            Some(ContactPhase {
                substep: r.f64("contact")?,
                resolved: r.flag("contact")?,
                first_substep: r.f64("contact")?,
                separated: r.opt_f64("contact")?,
                touch: r.f64("contact")?,
                penetrated: r.flag("contact")?,
                impulse: r.f64("contact")?,
                penetration: r.f64("contact")?,
                force: r.f64("contact")?,
            })
        } else {
            None
        };
        let trail_len = r.usize("impact trail")?;
        if trail_len > 2 {
            return Err(Error::Input(format!(
                "{source}: {trail_len} sub-step ends of the impact in progress, allowed at most 2"
            )));
        }
        let earlier = (0..trail_len)
            .map(|_| Ok((r.f64("impact trail")?, r.vec("impact trail")?)))
            .collect::<Result<Vec<_>, Error>>()?;
        let impact_trail = ImpactTrail {
            earlier,
            end: r.f64("impact trail")?,
        };
        let factor = if r.flag("factorisation")? {
            let frame = (r.f64("factorisation")?, r.f64("factorisation")?);
            let values = r.vec("factorisation")?;
            Some(Arc::new(FactorState { values, frame }))
        } else {
            None
        };
        if r.pos != body.len() {
            return Err(Error::Input(format!(
                "{source}: {} unexpected bytes after the snapshot at byte {}",
                body.len() - r.pos,
                r.pos
            )));
        }
        Ok(Self {
            fingerprint,
            state: State { t, u, v, a },
            lambda,
            step,
            total_iterations,
            total_factorizations,
            cutbacks,
            torque_work,
            theta,
            previous_alpha,
            clock,
            last_iterations,
            held_torque,
            impacts,
            events,
            contact_phase,
            impact_trail,
            factor,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::TorqueProfile;
    use std::path::PathBuf;

    fn table_config(file: &str) -> Config {
        let mut cfg = Config::default();
        cfg.torque.profile = TorqueProfile::Table;
        cfg.torque.file = Some(PathBuf::from(file));
        cfg
    }

    #[test]
    fn the_fingerprint_ignores_file_paths_but_sees_a_table_value_and_a_moved_mesh_node() {
        let mesh = crate::mesh::generate(&Config::default()).unwrap();
        let table = TorqueTable::parse("time_s,torque_Nm\n0,0\n0.5,0.2\n1,0\n", "t.csv").unwrap();
        let mut relative = table_config("t.csv");
        relative.mesh.file = Some(PathBuf::from("m.msh"));
        let base = fingerprint(&relative, &mesh, Some(&table));
        // the same model through other paths, a longer end and other outputs
        let mut absolute = table_config("/data/run 1/t.csv");
        absolute.mesh.file = Some(PathBuf::from("/data/meshes/m.msh"));
        absolute.time.end = 9.0;
        absolute.output.plots = !absolute.output.plots;
        assert_eq!(fingerprint(&absolute, &mesh, Some(&table)), base);
        assert_eq!(base.differences(&base, &relative), None);

        let mut edited = table.clone();
        edited.torques[1] = 0.2000000001;
        let other = fingerprint(&relative, &mesh, Some(&edited));
        assert_eq!((other.config, other.mesh), (base.config, base.mesh));
        assert_ne!(other.torque_table, base.torque_table);
        let why = other.differences(&base, &relative).unwrap();
        assert_eq!(
            why,
            "the torque table (times and torques of torque.file = t.csv) differs"
        );
        let mut later = table.clone();
        later.times[2] = 1.5;
        assert_ne!(
            fingerprint(&relative, &mesh, Some(&later)).torque_table,
            base.torque_table
        );

        let mut moved = mesh.clone();
        moved.nodes[7][0] += 1e-12;
        let other = fingerprint(&relative, &moved, Some(&table));
        assert_eq!((other.config, other.torque_table), (base.config, base.torque_table));
        assert_ne!(other.mesh, base.mesh);
        let why = other.differences(&base, &relative).unwrap();
        assert!(
            why.starts_with("the mesh (") && why.contains("mesh.file = m.msh"),
            "{why}"
        );

        let mut denser = relative.clone();
        denser.material.density *= 2.0;
        let other = fingerprint(&denser, &moved, None);
        let why = other.differences(&base, &denser).unwrap();
        assert!(
            why.starts_with("the configuration's values, the mesh")
                && why.ends_with("torque table (times and torques of torque.file = t.csv) differ"),
            "{why}"
        );
    }

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
