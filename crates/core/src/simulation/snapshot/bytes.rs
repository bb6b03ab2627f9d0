//! The snapshot as bytes: the little-endian writer and the bounds-checked reader, and
//! [`Snapshot::to_bytes`] / [`Snapshot::from_bytes`] with the magic, the format version and the
//! trailing checksum (format in the parent module's doc).

use std::sync::Arc;

use super::super::events::{ContactEvent, ContactEventKind, ContactPhase, ImpactTrail};
use super::super::interface::BodySnapshot;
use super::super::Clock;
use super::Snapshot;
use crate::error::Error;
use crate::model::Fingerprint;
use crate::model::State;
use crate::newton::FactorState;
use crate::reduced::step::Factor;
use crate::reduced::ReducedState;
use crate::store::bytes::{Reader, Writer};
use crate::store::fnv1a;

/// Version of the byte format of [`Snapshot::to_bytes`] (3: the fingerprint in three parts, without
/// file paths; 4: the impact's last sub-step ends; 5: the reduced body's coordinates, velocities and step Jacobian; 6: the reduced deformable wall's
/// amplitudes and velocities).
pub const SNAPSHOT_VERSION: u32 = 6;

const MAGIC: &[u8; 8] = b"PFEMSNAP";

impl Snapshot {
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
        match self.body.previous_alpha {
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
        match &self.body.factor {
            Some(f) => {
                w.u8(1);
                w.f64(f.frame.0);
                w.f64(f.frame.1);
                w.vec(&f.values);
            }
            None => w.u8(0),
        }
        match &self.body.reduced {
            Some(r) => {
                w.u8(1);
                w.f64(r.theta);
                w.vec(&r.q);
                w.vec(&r.v);
                w.vec(&r.wall_q);
                w.vec(&r.wall_v);
                match &r.jacobian {
                    Some(j) => {
                        w.u8(1);
                        w.f64(j.step);
                        w.vec(&j.lu);
                        w.usize(j.pivots.len());
                        j.pivots.iter().for_each(|&p| w.usize(p));
                    }
                    None => w.u8(0),
                }
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
        let reduced = if r.flag("reduced body")? {
            Some(ReducedState {
                theta: r.f64("reduced body")?,
                q: r.vec("reduced body")?,
                v: r.vec("reduced body")?,
                wall_q: r.vec("reduced body")?,
                wall_v: r.vec("reduced body")?,
                jacobian: if r.flag("reduced body")? {
                    let step = r.f64("reduced body")?;
                    let lu = r.vec("reduced body")?;
                    let count = r.usize("reduced body")?;
                    let pivots = (0..count)
                        .map(|_| r.usize("reduced body"))
                        .collect::<Result<Vec<_>, Error>>()?;
                    if lu.len() != pivots.len() * pivots.len() || pivots.iter().any(|&p| p >= pivots.len()) {
                        return Err(Error::Input(format!(
                            "{source}: the reduced body's Jacobian is damaged"
                        )));
                    }
                    Some(Factor { step, lu, pivots })
                } else {
                    None
                },
            })
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
            clock,
            last_iterations,
            held_torque,
            impacts,
            events,
            contact_phase,
            impact_trail,
            body: BodySnapshot {
                previous_alpha,
                factor,
                reduced,
            },
        })
    }
}
