//! One orchestrator for everything a run writes besides `results.csv`: [`FrameWriters`].
//!
//! The simulation calls [`FrameWriters::frame`] for every step (step 0 included), then
//! [`FrameWriters::last_frame`] with the last state computed (however the run ended), and
//! [`FrameWriters::finish`] once at the end, with the run's [`History`]. The writers apply
//! the thinning themselves: a ParaView frame is written when `step % output.paraview_every == 0`
//! (`output.every` when unset), the animations and the viewer are offered the steps with
//! `step % output.every == 0`, and the last step goes to both whatever its number. They honour
//! the flags:
//!
//! | flag        | files                                              | written            |
//! |-------------|----------------------------------------------------|--------------------|
//! | `paraview`  | `pendulum.pvd`, `frames/step_NNNNN.vtu`            | as frames arrive   |
//! | `animation` | `displacement.gif`, `von_mises.gif`                | in `finish`        |
//! | `viewer`    | `viewer.html`                                      | in `finish`        |
//! | `plots`     | `theta.png`, `energy.png` (from the history)       | in `finish`        |
//!
//! With a wall ([`FrameWriters::with_wall`]) the ParaView frames carry the contact pressure and
//! the rigid wall is a block of its own (`wall.vtu`), the animations and the viewer draw the wall
//! (a hatched band left of its face), and the plots mark the impacts of the history (the contact
//! events, the rows of `events.csv`).
//!
//! A flag that is off means its files are not written at all. The animations and the viewer share
//! one bounded set of kept frames ([`KeptFrames`], at most `output.max_frames`), so memory does not
//! grow with the length of the run.
//!
//! ```no_run
//! # use pendulum_fem_core::{config::Config, Mesh};
//! # use pendulum_fem_render::{plot::History, Frame, FrameWriters};
//! # use pendulum_fem_run::prepare_output_dir;
//! # fn demo(cfg: &Config, mesh: &Mesh, out: Option<&std::path::Path>, frames: &[Frame<'_>], history: &History) -> Result<(), pendulum_fem_core::Error> {
//! let dir = prepare_output_dir(&cfg.output.dir, out, false)?; // before any computing
//! let mut writers = FrameWriters::new(&dir, mesh, &cfg.output, None)?;
//! for frame in frames {
//!     writers.frame(frame)?; // every step, step 0 included
//! }
//! if let Some(last) = frames.last() {
//!     writers.last_frame(last)?; // however the run ended
//! }
//! let written = writers.finish(history)?; // the history of the run's records
//! # Ok(()) }
//! ```

use std::path::{Path, PathBuf};

use super::anim::{self, AnimField, KeptFrame, KeptFrames, Scene};
use super::plot::{self, History};
use super::pvd::PvdWriter;
use super::{viewer, Frame};
use crate::config::Output;
use crate::{Error, Mesh};

/// The names of a run's files (one list for the driver, the writers and the output folder).
pub use pendulum_fem_run::outdir::names;

pub use crate::wall::WallOutput;

/// Which steps the frame writers take: `Some(stride)` per output that is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Thinning {
    /// ParaView frames.
    pub paraview: Option<usize>,
    /// Frames kept for the animations and the viewer.
    pub kept: Option<usize>,
}

impl Thinning {
    /// Whether any output takes `step` (the last step is taken anyway, see
    /// [`FrameWriters::last_frame`]).
    pub fn wants(&self, step: usize) -> bool {
        [self.paraview, self.kept]
            .into_iter()
            .flatten()
            .any(|stride| step.is_multiple_of(stride))
    }
}

/// Writes the frame outputs of one run into one folder.
#[derive(Debug)]
pub struct FrameWriters {
    dir: PathBuf,
    /// A copy of the mesh, so the writers borrow nothing from the simulation.
    mesh: Mesh,
    output: Output,
    wall_x: Option<f64>,
    pvd: Option<PvdWriter>,
    kept: Option<KeptFrames>,
    /// The pendulum's nodes, `0..pendulum_nodes`, turn with θ in the pictures; the nodes of the
    /// bodies after it (a deformable wall) do not.
    pendulum_nodes: usize,
    /// The last step written to ParaView and offered to the kept frames.
    last_pvd: Option<usize>,
    last_kept: Option<usize>,
}

impl FrameWriters {
    /// Prepares writing into `dir` (created if missing; an empty `pendulum.pvd` is written at once
    /// when ParaView output is on). `wall_x` draws a wall line at that `x` \[m\] in the pictures.
    pub fn new(dir: &Path, mesh: &Mesh, output: &Output, wall_x: Option<f64>) -> Result<Self, Error> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let pvd = if output.paraview {
            Some(PvdWriter::new(dir)?)
        } else {
            None
        };
        let kept = (output.animation || output.viewer).then(|| KeptFrames::new(output.max_frames));
        Ok(Self {
            dir: dir.to_path_buf(),
            mesh: mesh.clone(),
            output: output.clone(),
            wall_x,
            pendulum_nodes: mesh.num_nodes(),
            pvd,
            kept,
            last_pvd: None,
            last_kept: None,
        })
    }

    /// Adds the wall: the ParaView frames get the contact pressure and a rigid wall's block (see
    /// [`PvdWriter::set_wall`]); the pictures draw a rigid wall at its face (as `wall_x` of
    /// [`FrameWriters::new`] does; a deformable wall is a body of the mesh and drawn as such, see
    /// [`FrameWriters::with_pendulum_nodes`]).
    pub fn with_wall(mut self, wall: WallOutput) -> Result<Self, Error> {
        if wall.rigid {
            self.wall_x = Some(wall.face_x);
        }
        if let Some(pvd) = &mut self.pvd {
            pvd.set_wall(wall)?;
        }
        Ok(self)
    }

    /// A model of several bodies: the mesh's nodes `0..n` are the pendulum's (they turn with θ
    /// in the pictures); the bodies after it (their triangles after the pendulum's, such as a
    /// deformable wall) are drawn too, displaced but not turned. The default is every node.
    pub fn with_pendulum_nodes(mut self, n: usize) -> Self {
        self.pendulum_nodes = n.min(self.mesh.num_nodes());
        self
    }

    /// Continues the frame outputs of a restarted run in `dir`: `earlier` are the `(step, time)`
    /// of the steps already computed (up to the checkpoint). Their ParaView frames (the steps on the
    /// `output.paraview_every` stride, as an uninterrupted run writes them) stay in `pendulum.pvd`;
    /// the animations and the viewer show the frames from the checkpoint on.
    pub fn resume(
        dir: &Path,
        mesh: &Mesh,
        output: &Output,
        wall_x: Option<f64>,
        earlier: &[(usize, f64)],
    ) -> Result<Self, Error> {
        let mut w = Self::new(dir, mesh, output, wall_x)?;
        if w.pvd.is_some() {
            let stride = output.paraview_stride();
            let kept: Vec<(usize, f64)> = earlier
                .iter()
                .copied()
                .filter(|(step, _)| step.is_multiple_of(stride))
                .collect();
            let entries = kept
                .iter()
                .map(|(step, time)| (*time, format!("{}/step_{step:05}.vtu", super::pvd::FRAMES_DIR)))
                .collect();
            w.pvd = Some(PvdWriter::resume(dir, entries)?);
            w.last_pvd = kept.last().map(|(step, _)| *step);
        }
        Ok(w)
    }

    /// Whether [`FrameWriters::frame`] would write anything for `step`.
    pub fn wants(&self, step: usize) -> bool {
        self.clone_thinning().wants(step)
    }

    /// The thinning rule, detached from the writers (for a caller that hands them to a thread).
    pub fn clone_thinning(&self) -> Thinning {
        Thinning {
            paraview: self.pvd.is_some().then(|| self.output.paraview_stride()),
            kept: self.kept.is_some().then(|| self.output.every.max(1)),
        }
    }

    /// Offers the state after one step (call for every step, including step 0).
    pub fn frame(&mut self, frame: &Frame<'_>) -> Result<(), Error> {
        let pvd = frame.step.is_multiple_of(self.output.paraview_stride());
        let kept = frame.step.is_multiple_of(self.output.every.max(1));
        self.write(frame, pvd, kept)
    }

    /// Offers the last state of the run (call once, after the last [`FrameWriters::frame`]): written
    /// to every output that has not had this step yet, so that every output ends on the last step.
    pub fn last_frame(&mut self, frame: &Frame<'_>) -> Result<(), Error> {
        let pvd = self.last_pvd != Some(frame.step);
        let kept = self.last_kept != Some(frame.step);
        self.write(frame, pvd, kept)
    }

    fn write(&mut self, frame: &Frame<'_>, to_pvd: bool, to_kept: bool) -> Result<(), Error> {
        let to_pvd = to_pvd && self.pvd.is_some();
        let to_kept = to_kept && self.kept.is_some();
        if !(to_pvd || to_kept) {
            return Ok(());
        }
        let n = self.mesh.num_nodes();
        let lengths = [
            ("displacement", frame.displacement.len()),
            ("velocity", frame.velocity.len()),
            ("acceleration", frame.acceleration.len()),
            ("von_mises", frame.von_mises.len()),
            ("cauchy", frame.cauchy.len()),
        ];
        if let Some((name, len)) = lengths.iter().find(|(_, len)| *len != n) {
            return Err(Error::Input(format!(
                "frame at step {} (t = {} s): {len} `{name}` values for a mesh of {n} nodes",
                frame.step, frame.time
            )));
        }
        if let (true, Some(pvd)) = (to_pvd, &mut self.pvd) {
            pvd.write_frame(&self.mesh, frame)?;
            self.last_pvd = Some(frame.step);
        }
        if let (true, Some(kept)) = (to_kept, &mut self.kept) {
            kept.push(KeptFrame::from_frame_of_bodies(
                &self.mesh.nodes,
                self.pendulum_nodes,
                frame,
            ));
            self.last_kept = Some(frame.step);
        }
        Ok(())
    }

    /// Writes the end-of-run outputs and returns every path written during the run. `history` is
    /// the run's (the plots are drawn from it; the viewer's θ curve comes from it when it holds two
    /// records or more, else from the kept frames).
    pub fn finish(self, history: &History) -> Result<Vec<PathBuf>, Error> {
        let mut paths = self.pvd.map(PvdWriter::into_paths).unwrap_or_default();
        let frames = self.kept.map(KeptFrames::into_frames).unwrap_or_default();
        if !frames.is_empty() {
            let scene = Scene::new(&self.mesh.nodes, &frames, self.output.magnification, self.wall_x);
            if self.output.animation {
                for (name, field) in [
                    (names::DISPLACEMENT_GIF, AnimField::Displacement),
                    (names::VON_MISES_GIF, AnimField::VonMises),
                ] {
                    let path = self.dir.join(name);
                    anim::write_gif(&path, &self.mesh, &frames, field, &scene)?;
                    paths.push(path);
                }
            }
            if self.output.viewer {
                let path = self.dir.join(names::VIEWER_HTML);
                let run = self
                    .dir
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                let title = format!("pendulum-fem: {run}");
                viewer::write_viewer(&path, &self.mesh, &frames, &scene, Some(history), &title)?;
                paths.push(path);
            }
        }
        if self.output.plots {
            let path = self.dir.join(names::THETA_PNG);
            plot::write_theta_png(&path, history)?;
            paths.push(path);
            let path = self.dir.join(names::ENERGY_PNG);
            plot::write_energy_png(&path, history)?;
            paths.push(path);
        }
        Ok(paths)
    }
}
