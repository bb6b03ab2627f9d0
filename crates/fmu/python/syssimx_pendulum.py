"""A syssimx component for the PendulumFem FMU with exact rollback through FMI 2.0 FMU states.

syssimx's ``FMUComponent`` cannot roll back (its ``FMUPendulum`` example re-instantiates from
``theta_start``/``omega_start``, which loses the deformation, the held torque and the contact
counters). ``PendulumFMU`` adds ``snapshot_state``/``restore_state`` on top of fmpy's
``getFMUstate``/``setFMUstate``: the FMU's complete state (fields, solver factorisation, held
input, counters), so that syssimx's hybrid algorithm and ``checkpoint()``/``restore_checkpoint()``
repeat a step bit for bit.

    from syssimx import System, Connection
    from syssimx_pendulum import PendulumFMU

    pendulum = PendulumFMU("pendulum", "target/fmu/PendulumFem.fmu")
    pendulum.set_parameters(theta_start=0.35)

Each snapshot holds one FMU state of the live instance (the complete fields, so its size grows
with the mesh); it is freed with the ``FMUStateHandle`` (garbage collection), or left to the
process when the instance was released first (an FMU state must not outlive its instance's
library).
"""

from __future__ import annotations

import weakref
from typing import Any

from syssimx.components.fmu import FMUComponent


class FMUStateHandle:
    """One ``fmi2FMUstate`` of one instance, freed when the handle is collected."""

    __slots__ = ("_owner", "_slave", "state", "time", "__weakref__")

    def __init__(self, owner: "PendulumFMU", slave: Any, state: Any, time: float):
        self._owner = weakref.ref(owner)
        self._slave = slave
        self.state = state
        self.time = time

    def alive(self) -> bool:
        """Whether the instance that made the state is still the owner's live instance."""
        owner = self._owner()
        return owner is not None and owner._instance is self._slave

    def free(self) -> None:
        """Frees the FMU state (once) while its instance lives."""
        if self.state is not None and self.alive():
            self._slave.freeFMUstate(self.state)
        self.state = None

    def __del__(self):
        try:
            self.free()
        except Exception:  # interpreter shutdown: the library may be gone
            pass


class PendulumFMU(FMUComponent):
    """``FMUComponent`` with ``snapshot_state``/``restore_state`` through FMU states."""

    def snapshot_state(self) -> FMUStateHandle:
        """The complete state now (an FMI 2.0 FMU state of the instance)."""
        slave = self._require_instance()
        return FMUStateHandle(self, slave, slave.getFMUstate(), self.t)

    def restore_state(self, snapshot: FMUStateHandle, t: float) -> None:
        """Returns the FMU to ``snapshot`` (taken at time ``t``) and refreshes the outputs."""
        if not isinstance(snapshot, FMUStateHandle) or not snapshot.alive() or snapshot.state is None:
            raise ValueError(f"{self.name}: snapshot is not a live FMU state of this instance")
        self._require_instance().setFMUstate(snapshot.state)
        self.t = t
        self._update_output_states(t)
