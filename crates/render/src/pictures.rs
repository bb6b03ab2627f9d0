//! The pictures and ParaView files of a run, as an observer of the run driver
//! ([`pendulum_fem_run::RunObserver`]): the frames go to a writer thread of their own
//! ([`FrameWriters`] on it: ParaView frames, the frames kept for the animations and the viewer),
//! the records (the rows of `results.csv` and `impacts.csv`, a restarted run's earlier ones
//! included) go into the run's [`History`], and at the run's end the animations, the viewer and the
//! plots are written. [`attach`] is what the CLI puts in
//! [`RunOptions::observers`](pendulum_fem_run::RunOptions::observers).

use std::path::PathBuf;

use pendulum_fem_core::simulation::{Simulation, StepRecord};
use pendulum_fem_core::{Config, Error, Mesh};
use pendulum_fem_run::driver::{Attach, RunObserver, RunStart};
use pendulum_fem_run::StepPlan;

use crate::plot::History;
use crate::writers::{FrameWriters, WallOutput};

/// The observer that writes a run's pictures and ParaView files as `output.*` selects them.
pub fn attach() -> Attach {
    Attach::new(|start| Pictures::start(start).map(|p| Some(Box::new(p) as Box<dyn RunObserver>)))
}

/// A run's pictures: the frame writer thread, whether frames are sent to it at all, and the
/// run's history.
struct Pictures {
    writer: FrameWriter,
    /// Some frame output is on (ParaView, animations or viewer); the plots are drawn at the end
    /// either way.
    wants_frames: bool,
    /// The records so far, for the plots and the viewer's θ curve (empty when neither is on).
    history: History,
    /// Whether the records go into the history.
    wants_history: bool,
    /// The contact events up to the last record taken (the rows `events.csv` has then).
    events: usize,
}

impl Pictures {
    fn start(start: &RunStart<'_>) -> Result<Self, Error> {
        let (cfg, sim, out_dir) = (start.config, start.sim, start.out_dir);
        let o = &cfg.output;
        if o.paraview {
            if let Some(warning) = output_size_warning(cfg, &sim.model.mesh) {
                eprintln!("{warning}");
            }
        }
        // the wall (when there is one) is drawn in the pictures and is a block of the ParaView output
        let wall = WallOutput::of(cfg, &sim.model.mesh);
        let wall_x = wall.as_ref().filter(|w| w.rigid).map(|w| w.face_x);
        let writers = match start.resumed.is_empty() {
            true => FrameWriters::new(out_dir, &sim.model.mesh, o, wall_x)?,
            false => FrameWriters::resume(out_dir, &sim.model.mesh, o, wall_x, start.resumed)?,
        };
        // a second body (a deformable wall) is drawn displaced, not turned with the pendulum
        let writers = writers.with_pendulum_nodes(sim.model.bodies[0].nodes.end);
        let writers = match wall {
            Some(wall) => writers.with_wall(wall)?,
            None => writers,
        };
        let wants_history = o.plots || o.viewer;
        Ok(Self {
            writer: FrameWriter::start(writers),
            wants_frames: o.paraview || o.animation || o.viewer,
            history: match wants_history {
                true => History::of_records(start.earlier),
                false => History::default(),
            },
            wants_history,
            events: 0,
        })
    }
}

impl RunObserver for Pictures {
    fn record(&mut self, sim: &mut Simulation, record: &StepRecord, resumed: bool) -> Result<(), Error> {
        if self.wants_history {
            self.history.push(record);
            self.events = sim.contact_events().len();
        }
        if self.wants_frames && self.writer.wants(record.step) && !resumed {
            self.writer.send(sim.frame_data(record.theta), false)?;
        }
        Ok(())
    }

    fn substeps(&mut self, records: &[StepRecord]) -> Result<(), Error> {
        if self.wants_history {
            records.iter().for_each(|r| self.history.push(r));
        }
        Ok(())
    }

    fn sync(&mut self) -> Result<(), Error> {
        self.writer.sync()
    }

    fn finish(mut self: Box<Self>, sim: &mut Simulation, last: &StepRecord) -> Result<Vec<PathBuf>, Error> {
        // the last state is the last frame, whether the run completed, stopped or failed, unless
        // its record was refused for a NaN or an infinity: no frame holds one
        let sent = match self.wants_frames && last.first_non_finite().is_none() {
            true => self.writer.send(sim.frame_data(last.theta), true),
            false => Ok(()),
        };
        let events = sim.contact_events();
        self.history.set_impacts(&events[..self.events.min(events.len())]);
        let finished = self.writer.finish(&self.history);
        sent?;
        finished
    }
}

/// Estimated output above which a run warns before it starts \[bytes\].
pub const LARGE_OUTPUT_BYTES: u64 = 1_000_000_000;

/// A warning naming the estimated size of the ParaView frames when it exceeds
/// [`LARGE_OUTPUT_BYTES`], with the keys that reduce it; `None` below.
pub fn output_size_warning(cfg: &Config, mesh: &Mesh) -> Option<String> {
    let steps = StepPlan::of(&cfg.time).steps();
    let stride = cfg.output.paraview_stride();
    let frames = (steps / stride + 2) as u64;
    let per_frame = crate::pvd::estimated_frame_bytes(mesh);
    let total = frames * per_frame;
    (total > LARGE_OUTPUT_BYTES).then(|| {
        let suggested = (total / (LARGE_OUTPUT_BYTES / 2)).max(2) * stride as u64;
        format!(
            "warning: this run will write about {:.1} GB of ParaView frames ({frames} frames of about {:.2} MB); \
             set output.paraview_every = {suggested} (or more) or output.paraview = false to write less",
            total as f64 / 1e9,
            per_frame as f64 / 1e6
        )
    })
}

/// Frame outputs written on a thread of their own, so that serialising ParaView files and keeping
/// frames for the pictures overlaps the time stepping. The channel holds at most
/// [`FRAME_QUEUE`] frames, so memory stays bounded when the writer falls behind.
struct FrameWriter {
    /// Frames (and whether each is the run's last), or a request to confirm that every frame
    /// before it is written.
    sender: Option<std::sync::mpsc::SyncSender<FrameMessage>>,
    handle: Option<std::thread::JoinHandle<Result<FrameWriters, Error>>>,
    /// The thinning of the writers (they live on the thread).
    wants: crate::writers::Thinning,
}

/// What the run sends to the frame writer thread.
enum FrameMessage {
    /// A frame, and whether it is the run's last.
    Frame(pendulum_fem_core::simulation::FrameData, bool),
    /// Answer on this channel once every frame before has been written.
    Sync(std::sync::mpsc::Sender<()>),
}

/// Frames waiting for the writer thread at most.
const FRAME_QUEUE: usize = 4;

impl FrameWriter {
    fn start(mut writers: FrameWriters) -> Self {
        let wants = writers.clone_thinning();
        let (sender, receiver) = std::sync::mpsc::sync_channel::<FrameMessage>(FRAME_QUEUE);
        let handle = std::thread::spawn(move || {
            for message in receiver {
                match message {
                    FrameMessage::Frame(data, true) => writers.last_frame(&data.as_frame())?,
                    FrameMessage::Frame(data, false) => writers.frame(&data.as_frame())?,
                    FrameMessage::Sync(done) => {
                        let _ = done.send(());
                    }
                }
            }
            Ok(writers)
        });
        Self {
            sender: Some(sender),
            handle: Some(handle),
            wants,
        }
    }

    /// Whether the writers take a frame of `step` (see [`FrameWriters::wants`]).
    fn wants(&self, step: usize) -> bool {
        self.wants.wants(step)
    }

    /// Queues a frame (`last`: the last state of the run); if the writer thread has stopped with an
    /// error, returns that error.
    fn send(&mut self, data: pendulum_fem_core::simulation::FrameData, last: bool) -> Result<(), Error> {
        let sent = self
            .sender
            .as_ref()
            .map(|s| s.send(FrameMessage::Frame(data, last)).is_ok())
            .unwrap_or(false);
        if sent {
            return Ok(());
        }
        self.sender = None;
        Err(self.join_error())
    }

    /// Waits until every frame sent so far is written (before a checkpoint); if the writer
    /// thread has stopped with an error, returns that error.
    fn sync(&mut self) -> Result<(), Error> {
        let (done, wait) = std::sync::mpsc::channel();
        let confirmed = self
            .sender
            .as_ref()
            .is_some_and(|s| s.send(FrameMessage::Sync(done)).is_ok() && wait.recv().is_ok());
        if confirmed {
            return Ok(());
        }
        self.sender = None;
        Err(self.join_error())
    }

    fn join_error(&mut self) -> Error {
        match self.handle.take().map(|h| h.join()) {
            Some(Ok(Err(e))) => e,
            Some(Err(_)) => Error::Input("the frame writer thread panicked".into()),
            _ => Error::Input("the frame writer stopped unexpectedly".into()),
        }
    }

    /// Waits for the queued frames, then writes the animations, the viewer and the plots of
    /// `history`.
    fn finish(mut self, history: &History) -> Result<Vec<PathBuf>, Error> {
        drop(self.sender.take());
        let handle = self.handle.take().ok_or_else(|| self.join_error())?;
        let writers = handle
            .join()
            .map_err(|_| Error::Input("the frame writer thread panicked".into()))??;
        writers.finish(history)
    }
}
