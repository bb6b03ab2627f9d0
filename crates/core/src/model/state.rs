//! The state of the full model's fields at one time.

/// Kinematic state at one time: nodal displacement, velocity and acceleration (interleaved).
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Time \[s\].
    pub t: f64,
    /// Displacement \[m\].
    pub u: Vec<f64>,
    /// Velocity \[m/s\].
    pub v: Vec<f64>,
    /// Acceleration \[m/s²\].
    pub a: Vec<f64>,
}
