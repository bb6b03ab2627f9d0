//! The wall and contact outputs (`gap`, `contact_force`, `contact_count`, `impact`), read in one
//! place: [`contact_outputs`].
//!
//! With a wall (`wall_kind` 1), they are the stepper's: the smallest gap of the head's arc to the
//! face and the wall's normal force ([`pendulum_fem_core::terms::WallContact`]), and the impacts the
//! stepper counted (an impact counts when the head first penetrates). Without one, `gap` is the
//! distance of the deformed head to the plane `x = wall_x` and nothing touches
//! ([`Simulation::gap`] either way).

use pendulum_fem_core::Simulation;

/// The contact outputs of one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOutputs {
    /// Smallest signed distance from the head to the wall face \[m\]; negative: penetration.
    pub gap: f64,
    /// Normal force of the wall on the head \[N\] (0 without a wall).
    pub force: f64,
    /// Impacts so far.
    pub count: i32,
    /// An impact started during the last `doStep` (the flag the instance holds).
    pub impact: bool,
}

/// The contact outputs of the current state of `sim`; `impact` is the instance's flag.
pub fn contact_outputs(sim: &Simulation, impact: bool) -> ContactOutputs {
    ContactOutputs {
        gap: sim.gap(),
        force: sim.contact_force(),
        count: sim.impacts() as i32,
        impact,
    }
}
