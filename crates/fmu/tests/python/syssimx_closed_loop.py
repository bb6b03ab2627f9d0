"""Test 4: syssimx closed loop. A PD controller component drives the FMU's `tau` from θ and ω,
`tau = K_p (θ_ref − θ) − K_d ω` with θ_ref = 0.3 rad; the pendulum (syssimx_pendulum.PendulumFMU,
rollback through FMU states) settles within 2 s, and from then on θ equals the exact static balance
K_p (θ_ref − θ) = m g d sin θ within 1e-4 rad (with the centre of mass at (e, −d) in the
hanging reference configuration, the gravity moment is m g (d sin θ + e cos θ); e is ~0 for the
symmetric pendulum). Also: a checkpoint/restore of the pendulum in the
middle of the run repeats the following steps bit for bit.

usage: syssimx_closed_loop.py FMU MASS_KG COM_DISTANCE_M COM_OFFSET_X_M"""

import math
import os
import sys

import numpy as np
from syssimx import Connection, CoSimComponent, PortSpec, PortType, System
from syssimx.components.fmu import clear_extraction_cache

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "python"))
from syssimx_pendulum import PendulumFMU  # noqa: E402

from fmu_common import report  # noqa: E402

path, m, d, e = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
G, THETA_REF, KP, KD, DT = 9.81, 0.3, 3.5, 1.0, 0.01


def magnitude(v):
    return float(v.magnitude) if hasattr(v, "magnitude") else float(v)


class PD(CoSimComponent):
    """tau = K_p (θ_ref − θ) − K_d ω (algebraic: direct feedthrough from θ and ω)."""

    def __init__(self, name):
        super().__init__(name)
        self.input_specs = {"theta": PortSpec("theta", PortType.REAL, "in", "rad"),
                            "omega": PortSpec("omega", PortType.REAL, "in", "rad/s")}
        self.output_specs = {"tau": PortSpec("tau", PortType.REAL, "out", "N*m")}
        self.parameters = {"kp": KP, "kd": KD, "theta_ref": THETA_REF}

    def _initialize_component(self, t0):
        pass

    def _detect_direct_feedthrough(self):
        self.direct_feedthrough = {"tau": {"theta", "omega"}}
        return self.direct_feedthrough

    def _do_step_internal(self, t, dt):
        pass

    def _update_output_states(self, t=None, event_names=None):
        th, om = self.inputs["theta"].get(), self.inputs["omega"].get()
        th = magnitude(th) if th is not None else THETA_REF
        om = magnitude(om) if om is not None else 0.0
        p = self.parameters
        self.outputs["tau"].set(p["kp"] * (p["theta_ref"] - th) - p["kd"] * om, t=t)


pendulum = PendulumFMU("pendulum", path)
pendulum.set_parameters(theta_start=0.0)
controller = PD("controller")
system = System("pd_pendulum")
system.add_component(pendulum)
system.add_component(controller)
system.add_connection(Connection("pendulum", "theta", "controller", "theta"))
system.add_connection(Connection("pendulum", "omega", "controller", "omega"))
system.add_connection(Connection("controller", "tau", "pendulum", "tau"))
system.initialize(t0=0.0)
system.run(t0=0.0, tf=1.0, dt=DT)

# rollback: checkpoint at t = 1 s, 20 steps, restore, the same 20 steps again
probe = []
for attempt in range(2):
    if attempt == 0:
        checkpoint = pendulum.checkpoint()
    else:
        pendulum.restore_checkpoint(checkpoint)
    t, run = 1.0, []
    for _ in range(20):
        pendulum.set_inputs({"tau": 0.5}, t=t)
        pendulum.do_step(t, DT)
        t = round(t + DT, 12)
        run.append(magnitude(pendulum.outputs["theta"].get()).hex())
    probe.append(run)
pendulum.restore_checkpoint(checkpoint)
rollback_identical = probe[0] == probe[1]

system.run(t0=1.0, tf=3.0, dt=DT)
times, hist = pendulum.get_history_arrays(["theta", "omega"])
times = np.asarray(times, dtype=float)
theta = np.asarray([magnitude(v) for v in hist["theta"]], dtype=float)
omega = np.asarray([magnitude(v) for v in hist["omega"]], dtype=float)

# exact static balance K_p (θ_ref − θ) = m g (d sin θ + e cos θ), by Newton from θ_ref
th = THETA_REF
for _ in range(50):
    f = KP * (THETA_REF - th) - m * G * (d * math.sin(th) + e * math.cos(th))
    th -= f / (-KP - m * G * (d * math.cos(th) - e * math.sin(th)))
pendulum.free()
clear_extraction_cache()

settled = times >= 2.0 - 1e-9
err = float(np.max(np.abs(theta[settled] - th)))
report(rollback_identical and err <= 1e-4 and settled.sum() >= 100, theta_balance_rad=th,
       theta_final_rad=float(theta[-1]), max_error_after_2s_rad=err,
       max_abs_omega_after_2s=float(np.max(np.abs(omega[settled]))), samples_after_2s=int(settled.sum()),
       rollback_identical=rollback_identical, kp=KP, kd=KD, mass_kg=m, com_distance_m=d,
       com_offset_x_m=e)
