"""pendulum_fem: a finite-element simulator of a deformable pendulum, stepped from Python.

A thin steel plate (a rod with a ring-shaped head) swings on a hinge under gravity, hyperelastic,
optionally driven by a torque at the pivot (the NGSolve tutorial "FEM Pendulum"). The simulation
runs in Rust; this package drives its stepper:

>>> import pendulum_fem
>>> sim = pendulum_fem.Simulation(**{"initial.angle_deg": 30})
>>> sim.step(0.01)          # one step of 10 ms (the GIL is released)
>>> sim.theta, sim.omega    # proxy angle [rad] and angular velocity [rad/s]
>>> sim.tau = 0.5           # hold a pivot torque of 0.5 N m
>>> rows = sim.run(1.0)     # the columns of results.csv up to t = 1 s, as numpy arrays

With a rigid wall (``Simulation(**{"wall.kind": "rigid"})``) the stepper locates and resolves every
impact of the head; ``gap``, ``contact_force``, ``impacts``, ``in_contact`` and ``events`` (the rows
of the CLI's ``events.csv``) read it, and ``run`` adds the contact columns.

``pendulum_fem.syssimx`` (imported on its own, it needs ``syssimx``) wraps the simulation as a
syssimx co-simulation component.
"""

from ._core import (
    ConvergenceError,
    OutsideModelError,
    Simulation,
    UnknownKeyError,
    __version__,
    csv_columns,
    event_columns,
)
from .sweep import sweep

__all__ = [
    "Simulation",
    "ConvergenceError",
    "OutsideModelError",
    "UnknownKeyError",
    "csv_columns",
    "event_columns",
    "__version__",
    "sweep",
]


def _rebuild_simulation(config_toml: str, snapshot: bytes) -> Simulation:
    """Unpickles a :class:`Simulation`: its configuration (TOML) and its snapshot."""
    return Simulation._from_state(config_toml, snapshot)
