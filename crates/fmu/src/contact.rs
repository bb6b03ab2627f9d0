//! The wall and contact outputs (`gap`, `contact_force`, `contact_count`, `impact`), read in one
//! place: [`contact_outputs`].
//!
//! The model the FMU builds has no wall term, so these are the values that are true for a pendulum
//! swinging free of a wall at `x = wall_x`: the gap is measured honestly from the deformed head,
//! nothing touches, nothing is counted. When the stepper reports contact, this function is the one
//! to read its contact force, impact counter and impact flag instead.

use pendulum_fem::Simulation;

/// The boundary of the mesh that faces the wall: the outer circle of the head.
pub const HEAD_BOUNDARY: &str = "contact_head";

/// The contact outputs of one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOutputs {
    /// `min_a x_a − wall_x` over the nodes of the head's outer circle in the current (deformed)
    /// configuration \[m\]; negative would mean penetration.
    pub gap: f64,
    /// Force of the wall on the head \[N\]: 0 (no wall term in the model).
    pub force: f64,
    /// Impacts so far: the count the instance holds (0: no wall term, no impact).
    pub count: i32,
    /// An impact started during the last step: the flag the instance holds (false without a wall).
    pub impact: bool,
}

/// The contact outputs of the current state of `sim` for the wall face `x = wall_x` \[m\].
///
/// Returns today: `gap` from the deformed positions of the head's outer-circle nodes
/// ([`HEAD_BOUNDARY`]), `force = 0`, and `count`, `impact` as held by the instance (which never
/// changes them without a wall: 0 and false).
pub fn contact_outputs(sim: &Simulation, wall_x: f64, count: i32, impact: bool) -> ContactOutputs {
    let mesh = &sim.model.mesh;
    let u = sim.displacement();
    let head_min_x = mesh
        .edges_named(HEAD_BOUNDARY)
        .flat_map(|e| e.nodes)
        .map(|n| mesh.nodes[n][0] + u[2 * n])
        .fold(f64::INFINITY, f64::min);
    ContactOutputs {
        gap: head_min_x - wall_x,
        force: 0.0,
        count,
        impact,
    }
}
