//! Writers and readers: VTU/PVD for ParaView, Gmsh `.msh`, CSV, plots, animations, the HTML viewer.

pub mod anim;
pub mod csv;
mod font;
pub mod outdir;
pub mod plot;
pub mod pvd;
mod raster;
pub mod viewer;
pub mod vtu;
pub mod writers;

pub use outdir::prepare_output_dir;
pub use writers::FrameWriters;

/// Values of one field at every mesh node (vertices and mid-edge nodes).
#[derive(Clone, Copy, Debug)]
pub enum FieldData<'a> {
    /// One value per node.
    Scalar(&'a [f64]),
    /// `[x, y]` per node.
    Vector(&'a [[f64; 2]]),
    /// Symmetric 2-D tensor `[xx, yy, xy]` per node.
    Tensor(&'a [[f64; 3]]),
}

/// A named nodal field.
#[derive(Clone, Copy, Debug)]
pub struct Field<'a> {
    /// Name shown in ParaView.
    pub name: &'a str,
    /// Values.
    pub data: FieldData<'a>,
}

/// The state of the pendulum at one written time, with everything the frame writers need.
/// All arrays are per mesh node (vertices and mid-edge nodes).
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    /// Step number (0 is the initial state).
    pub step: usize,
    /// Time \[s\].
    pub time: f64,
    /// Rigid-body proxy angle \[rad\] (unwrapped).
    pub theta: f64,
    /// Displacement \[m\].
    pub displacement: &'a [[f64; 2]],
    /// Velocity \[m/s\].
    pub velocity: &'a [[f64; 2]],
    /// Acceleration \[m/s²\].
    pub acceleration: &'a [[f64; 2]],
    /// Plane-stress von Mises stress \[Pa\].
    pub von_mises: &'a [f64],
    /// Cauchy stress `[σxx, σyy, σxy]` \[Pa\].
    pub cauchy: &'a [[f64; 3]],
}
