//! The crate's error type: every variant carries the context a user needs (which key, which
//! element, which step and time), and chains its cause.

use std::fmt;

/// Why the Newton solver gave up on one step.
#[derive(Clone, Debug, PartialEq)]
pub enum NewtonError {
    /// `max_iterations` reached; the last energy norm of the update and residual norm.
    MaxIterations {
        /// Iterations done.
        iterations: usize,
        /// Last `|Δuᵀ r|` \[J\].
        energy_norm: f64,
        /// Last residual norm \[N\].
        residual: f64,
        /// The forces in play at the last iterate: the largest nodal sum of the magnitudes of the
        /// terms' forces and the hinge reaction \[N\] (see [`crate::newton::FORCE_ROUNDING`]).
        forces: f64,
    },
    /// The tangent could not be factorised: not positive definite, and its `L D Lᵀ` met a zero
    /// pivot (see [`crate::linsolve::Cholesky::factor`]).
    SingularTangent {
        /// Iteration at which it happened.
        iteration: usize,
    },
    /// The residual or energy became infinite or NaN (an inverted element).
    NonFinite {
        /// Iteration at which it happened.
        iteration: usize,
    },
    /// The line search found no decrease of the incremental potential.
    LineSearch {
        /// Iteration at which it happened.
        iteration: usize,
        /// Residual norm \[N\].
        residual: f64,
    },
}

impl NewtonError {
    /// The iterations (linear solves) the failed solve made.
    pub fn iterations(&self) -> usize {
        match *self {
            Self::MaxIterations { iterations, .. } => iterations,
            Self::SingularTangent { iteration }
            | Self::NonFinite { iteration }
            | Self::LineSearch { iteration, .. } => iteration,
        }
    }
}

impl fmt::Display for NewtonError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::MaxIterations {
                iterations,
                energy_norm,
                residual,
                forces,
            } => write!(
                f,
                "Newton did not converge in {iterations} iterations (energy norm {energy_norm:.3e} J, residual \
                 {residual:.3e} N of forces in play {forces:.3e} N)"
            ),
            Self::SingularTangent { iteration } => {
                write!(
                    f,
                    "tangent matrix singular at Newton iteration {iteration} (neither L Lᵀ nor L D Lᵀ factorises it)"
                )
            }
            Self::NonFinite { iteration } => {
                write!(
                    f,
                    "non-finite energy or residual (inverted element) at Newton iteration {iteration}"
                )
            }
            Self::LineSearch { iteration, residual } => write!(
                f,
                "line search found no decrease at Newton iteration {iteration} (residual {residual:.3e} N)"
            ),
        }
    }
}

impl std::error::Error for NewtonError {}

/// The crate error.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// Invalid configuration or command-line value; the message names the key and the allowed range.
    Config(String),
    /// Impossible geometry; names the parameter.
    Geometry(String),
    /// Mesh generation failed or produced an invalid mesh.
    Mesh(String),
    /// An element of the reference mesh with non-positive Jacobian.
    InvertedElement {
        /// Element index.
        element: usize,
        /// Quadrature point index.
        quad_point: usize,
        /// The Jacobian determinant found.
        det_j: f64,
    },
    /// A time step failed after all cut-backs.
    TimeStep {
        /// Step number (1-based: the step that would reach `t + dt`).
        step: usize,
        /// Time at the start of the step \[s\].
        t: f64,
        /// Smallest step tried \[s\].
        dt: f64,
        /// The last Newton failure.
        source: NewtonError,
    },
    /// The initial elastic equilibrium (`initial.elastic = "equilibrium"`) could not be found.
    InitialEquilibrium {
        /// The Newton failure.
        source: NewtonError,
    },
    /// A file could not be read or written.
    Io {
        /// The file or folder.
        path: std::path::PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Invalid input data in a file (names the file and line).
    Input(String),
    /// The sparse factorisation could not be set up.
    LinearSolver(String),
    /// A modal analysis ([`crate::modal`]) failed: the message names the step (factorisation,
    /// constraints, Lanczos convergence, residual check) and what to change.
    Modal(String),
    /// The deformable wall's face met the head where the fixed sparsity pattern couples no
    /// nodes (the bodies deformed by more than its margin): the step is refused rather than solved
    /// with a truncated Jacobian ([`crate::terms::WallContact::uncoupled_contact`]).
    ContactOutsidePattern {
        /// Step number (1-based: the step that would reach `t + dt`).
        step: usize,
        /// Time of the (sub-)step end at which it was found \[s\].
        t: f64,
        /// Which head edge and face segment, where.
        message: String,
    },
    /// A step failed where the case leaves the model: the message names the cause (for example
    /// the head coming round the deformable wall's face, [`crate::terms::WallContact::behind_face`]).
    OutsideModel {
        /// Step number (1-based: the step that would reach `t + dt`).
        step: usize,
        /// Time at the start of the step \[s\].
        t: f64,
        /// The cause and what to change.
        message: String,
    },
    /// A quantity of a step came out NaN or infinite (see [`crate::simulation::StepRecord::check_finite`]):
    /// no result is ever one of those, so the step is refused, as a failed step is.
    NonFinite {
        /// Step number (0: the initial state; else the step that would reach `t`).
        step: usize,
        /// Time of that state \[s\].
        t: f64,
        /// The quantity, named as a sentence names it ("kinetic energy").
        quantity: &'static str,
        /// Its value: NaN, `inf` or `-inf`.
        value: f64,
    },
    /// The run was stopped because it diverged (the energy watchdog of `pendulum-fem run`).
    Divergence {
        /// Step at which it was detected.
        step: usize,
        /// Its time \[s\].
        t: f64,
        /// What was seen and what to try.
        message: String,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Config(m) => write!(f, "configuration: {m}"),
            Self::Geometry(m) => write!(f, "geometry: {m}"),
            Self::Mesh(m) => write!(f, "mesh: {m}"),
            Self::InvertedElement {
                element,
                quad_point,
                det_j,
            } => write!(
                f,
                "mesh: element {element} has a non-positive Jacobian {det_j:e} at quadrature point {quad_point}"
            ),
            Self::TimeStep { step, t, dt, source } => {
                write!(
                    f,
                    "time step {step} from t = {t:.6} s failed (smallest dt tried {dt:.3e} s): {source}. \
                     Try a smaller time.dt or time.max_rotation_deg, time.scheme = \"hht\" for fast spins, or more \
                     solver.max_iterations / solver.max_cutbacks"
                )
            }
            Self::InitialEquilibrium { source } => write!(
                f,
                "the initial elastic equilibrium failed ({source}); try initial.elastic = \"undeformed\""
            ),
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Input(m) => write!(f, "input: {m}"),
            Self::LinearSolver(m) => write!(f, "linear solver: {m}"),
            Self::Modal(m) => write!(f, "modal analysis: {m}"),
            Self::ContactOutsidePattern { step, t, message } => {
                write!(f, "time step {step} refused at t = {t:.6} s: {message}")
            }
            Self::OutsideModel { step, t, message } => {
                write!(f, "time step {step} from t = {t:.6} s is outside the model: {message}")
            }
            Self::NonFinite {
                step,
                t,
                quantity,
                value,
            } => write!(
                f,
                "step {step} (t = {t:.6} s): the {quantity} is {value}, and no result may be NaN or infinite: the \
                 computation left the range of floating-point numbers. Try a smaller time.dt or \
                 time.max_rotation_deg, time.scheme = \"hht\", or inputs nearer the model's range \
                 (initial.angular_velocity, the torque, gravity.g, the material's density and modulus)"
            ),
            Self::Divergence { step, t, message } => write!(f, "run stopped at step {step}, t = {t} s: {message}"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::TimeStep { source, .. } | Self::InitialEquilibrium { source } => Some(source),
            Self::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl Error {
    /// Wraps an I/O error with the path it concerns.
    pub fn io(path: impl Into<std::path::PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}
