"""The pendulum as a syssimx co-simulation component (needs ``syssimx``, 0.4.3 or later).

:class:`PendulumFem` is a :class:`syssimx.CoSimComponent` over :class:`pendulum_fem.Simulation`,
shaped like syssimx's own ``FEMPendulum`` example:

* input ``tau`` [N.m], the pivot torque, held over each macro step (zero-order hold);
* outputs ``theta`` [rad], ``omega`` [rad/s], ``alpha`` [rad/s^2] (``alpha`` follows ``tau`` at
  once: the only direct feedthrough), ``gap`` [m] (head to wall face, see
  :attr:`pendulum_fem.Simulation.gap`) and ``contact_count`` (an integer: the impacts on the wall
  so far, :attr:`pendulum_fem.Simulation.impacts`);
* ``snapshot_state``/``restore_state`` through the stepper's complete snapshot, so a rollback by
  syssimx's hybrid algorithm continues bit for bit as if the component had never advanced;
* a macro step longer than ``max_internal_step`` (default: the configuration's ``time.dt``) is
  split into internal steps by the FMU's rule (:func:`pendulum_fem._core.internal_steps`): a
  multiple of it takes steps of exactly that length, as the CLI does, other steps equal ones (the
  previous macro step's internal step when within rounding of it); a zero step only refreshes the
  outputs.

**Impacts.** With a wall (``**{"wall.kind": "rigid"}``) the stepper resolves each impact inside
the macro step, so the head can touch the wall and leave it between two communication points, and
``gap`` is positive at both. The parity of ``contact_count`` changes in every step with an impact:
register it as the event indicator (see :func:`impact_parity`) under a name that is not an output
of this component (an output named like the event, e.g. ``wall_hit``, would hide its event port),
and syssimx's hybrid algorithm locates the impact by rolling back::

    plant = PendulumFem("pendulum", **{"wall.kind": "rigid"})
    plant.add_event_indicator("wall_hit", impact_parity)

Parameters (``set_parameters`` before ``initialize``): ``config`` (a TOML path or dict, as for
:class:`pendulum_fem.Simulation`), ``overrides`` (a dict of the CLI's keys) and
``max_internal_step`` [s] (0: ``time.dt``). The model always has a torque input
(``torque.profile = "constant"`` unless the configuration names another profile, which the input
then replaces).
"""

from __future__ import annotations

import math
from typing import Any, Dict, List, Mapping, Optional, Union

try:
    from syssimx import CoSimComponent, PortSpec, PortType
except ImportError as error:  # pragma: no cover - depends on the environment
    raise ImportError(
        "pendulum_fem.syssimx needs syssimx: pip install 'pendulum-fem[syssimx]'"
    ) from error

from . import Simulation
from ._core import internal_steps

#: Marks this component's snapshots (``restore_state`` refuses others).
SNAPSHOT_MODE = "pendulum-fem"

INPUT_SPECS = {
    "tau": PortSpec("tau", PortType.REAL, direction="in", unit="N.m", description="pivot torque"),
}

OUTPUT_SPECS = {
    "theta": PortSpec("theta", PortType.REAL, direction="out", unit="rad", description="proxy angle"),
    "omega": PortSpec("omega", PortType.REAL, direction="out", unit="rad/s", description="angular velocity"),
    "alpha": PortSpec("alpha", PortType.REAL, direction="out", unit="rad/s^2", description="angular acceleration"),
    "gap": PortSpec("gap", PortType.REAL, direction="out", unit="m", description="head to wall face"),
    "contact_count": PortSpec(
        "contact_count", PortType.INT, direction="out", description="impacts on the wall so far"
    ),
}

#: Outputs that change with an input within the same instant (the rest follow only by stepping).
DIRECT_FEEDTHROUGH = {"theta": set(), "omega": set(), "alpha": {"tau"}, "gap": set(), "contact_count": set()}


def _magnitude(value: Any, unit: str) -> float:
    """A port value (a pint Quantity or a number) as a float in ``unit``."""
    if hasattr(value, "to"):
        return float(value.to(unit).magnitude)
    return float(value)


def impact_parity(component: "PendulumFem") -> float:
    """Event indicator of the impacts: +0.5 after an even number of impacts, -0.5 after an odd one
    (from the ``contact_count`` output), so that every impact is a sign change."""
    count = component.outputs["contact_count"].get()
    return 0.5 - (int(count or 0) % 2)


class PendulumFem(CoSimComponent):
    """The deformable pendulum of ``pendulum_fem`` as a syssimx component.

    Args:
        name: Unique name in the system.
        config: A TOML file, a dict of configuration keys, or ``None`` (the CLI's defaults).
        label: Display name (default ``name``).
        group: Grouping category (default ``"Plant"``).
        max_internal_step: Longest internal step [s]; ``None``: the configuration's ``time.dt``.
        **overrides: Configuration keys (``**{"initial.angle_deg": 0}`` or nested dicts).
    """

    def __init__(
        self,
        name: str,
        config: Union[str, Mapping[str, Any], None] = None,
        *,
        label: Optional[str] = None,
        group: str = "Plant",
        max_internal_step: Optional[float] = None,
        **overrides: Any,
    ) -> None:
        super().__init__(name, label, group)
        self.input_specs = dict(INPUT_SPECS)
        self.output_specs = dict(OUTPUT_SPECS)
        self._initialize_ports_from_specs()
        self.direct_feedthrough = {k: set(v) for k, v in DIRECT_FEEDTHROUGH.items()}
        # syssimx refuses to set a parameter whose current value is None: empty values instead
        self.parameters = {
            "config": config if config is not None else {},
            "overrides": dict(overrides),
            "max_internal_step": float(max_internal_step or 0.0),
        }
        self.sim: Optional[Simulation] = None
        self._max_step = 0.0
        # the internal step of the last macro step (reused within rounding, as the FMU does)
        self._last_internal_step: Optional[float] = None

    # ------------------------------------------------------------------ lifecycle
    def _initialize_component(self, t0: float) -> None:
        config = self.parameters["config"] or None
        self.sim = Simulation(config, **self.parameters["overrides"])
        # the torque input exists from the start (declared before the first step)
        self.sim.tau = self._input_tau()
        h = float(self.parameters["max_internal_step"])
        self._max_step = h if h > 0.0 else float(self.sim.config["time"]["dt"])
        self._last_internal_step = None

    def _input_tau(self) -> float:
        value = self.inputs["tau"].get()
        return 0.0 if value is None else _magnitude(value, "N*m")

    def _require_sim(self) -> Simulation:
        if self.sim is None:
            raise RuntimeError(f"[{self.name}] initialize() the component before stepping it.")
        return self.sim

    def reset(self) -> None:
        """Drops the simulation; ``initialize`` builds a new one."""
        super().reset()
        self.sim = None
        self._last_internal_step = None

    # ------------------------------------------------------------------ inputs and outputs
    def set_inputs(self, signals: Dict[str, Any], t: Optional[float] = None) -> None:
        super().set_inputs(signals, t)
        if "tau" in signals and self.sim is not None:
            self.sim.tau = self._input_tau()
            # α answers the torque at once (the direct feedthrough tau → alpha)
            self.outputs["alpha"].set(self.sim.alpha, t=t)

    def evaluate_outputs(self, inputs: Dict[str, Any], t: Optional[float] = None) -> Dict[str, Any]:
        if inputs:
            self.set_inputs(inputs, t=t)
        return {name: port.get() for name, port in self.outputs.items()}

    def _update_output_states(self, t: Optional[float] = None, event_names: Optional[List[str]] = None) -> None:
        if self.sim is not None:
            sim = self.sim
            self.outputs["theta"].set(sim.theta, t=t)
            self.outputs["omega"].set(sim.omega, t=t)
            self.outputs["alpha"].set(sim.alpha, t=t)
            self.outputs["gap"].set(sim.gap, t=t)
            self.outputs["contact_count"].set(sim.impacts, t=t)
        self._apply_event_ports(t, event_names)

    # ------------------------------------------------------------------ stepping
    def _do_step_internal(self, t: float, dt: float) -> None:
        sim = self._require_sim()
        if not (math.isfinite(dt) and dt >= 0.0):
            raise ValueError(f"[{self.name}] macro step dt = {dt} s: allowed finite and >= 0")
        self.internal_event_hints.clear()  # hints belong to the advance that reports them
        if dt == 0.0:
            return  # an output refresh (syssimx's initialization and algebraic loops)
        try:
            n, h = internal_steps(dt, self._max_step, self._last_internal_step)
        except ValueError as error:
            raise ValueError(f"[{self.name}] macro step dt = {dt} s: {error}") from None
        for _ in range(n):
            sim.step(h)
        self._last_internal_step = h

    # ------------------------------------------------------------------ rollback
    def snapshot_state(self) -> Dict[str, Any]:
        """The complete state of the stepper (opaque bytes), the component's time and the last
        internal step."""
        return {
            "mode": SNAPSHOT_MODE,
            "state": self._require_sim().snapshot(),
            "t": self.t,
            "last_internal_step": self._last_internal_step,
        }

    def restore_state(self, snapshot: Dict[str, Any], t: float) -> None:
        """Restores a :meth:`snapshot_state` of this component: later steps repeat bit for bit."""
        if not isinstance(snapshot, dict) or snapshot.get("mode") != SNAPSHOT_MODE:
            raise ValueError(f"[{self.name}] not a snapshot of a PendulumFem component")
        self._require_sim().restore(snapshot["state"])
        self._last_internal_step = snapshot.get("last_internal_step")
        self.internal_event_hints.clear()
        self.t = t
        self._update_output_states(t)
        if self._record_history:
            self._record_outputs(t)

    # ------------------------------------------------------------------ physical state
    def get_state(self) -> Dict[str, Dict[str, Any]]:
        """The rigid-body view of the state: θ, ω, α and the torque, with units."""
        sim = self._require_sim()
        return {
            "theta": {"value": sim.theta, "unit": "rad"},
            "omega": {"value": sim.omega, "unit": "rad/s"},
            "alpha": {"value": sim.alpha, "unit": "rad/s**2"},
            "tau": {"value": sim.tau, "unit": "N*m"},
        }

    def set_state(self, state: Dict[str, Dict[str, Any]], t: float) -> None:
        """Starts afresh from a rigid state (``theta``, ``omega``, optional ``tau``): a rigid
        rotation in elastic equilibrium, as the configuration's initial state is built."""
        overrides = dict(self.parameters["overrides"])
        if "theta" in state:
            overrides["initial.angle_deg"] = math.degrees(_magnitude(state["theta"]["value"], "rad"))
        if "omega" in state:
            overrides["initial.angular_velocity"] = _magnitude(state["omega"]["value"], "rad/s")
        self.sim = Simulation(self.parameters["config"] or None, **overrides)
        tau = _magnitude(state["tau"]["value"], "N*m") if "tau" in state else self._input_tau()
        self.sim.tau = tau
        self._last_internal_step = None
        self.t = t
        self._update_output_states(t)
