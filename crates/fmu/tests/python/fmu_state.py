"""Test 2: FMU state. With a varying torque input: get the state at t = 0.5 s, step on, set the
state, step again: bit-identical outputs; the same through serialize/deserialize (into the same
instance and into a fresh instance with the same parameters); two instances with different
parameters in one process, stepped alternately, give exactly what each gives alone.

usage: fmu_state.py FMU"""

import math
import sys

from fmu_common import Fmu, bits, report

fmu = Fmu(sys.argv[1])
H = 0.01


def drive(inst, t, steps):
    """`steps` communication steps from `t` with tau = 0.05 sin(3t) N m; outputs after each."""
    out = []
    for k in range(steps):
        inst.setReal([fmu.vr("tau")], [0.05 * math.sin(3.0 * t)])
        inst.doStep(currentCommunicationPoint=t, communicationStepSize=H)
        t = round(t + H, 12)
        out.append(bits(fmu.outputs(inst)))
    return t, out


a = fmu.instance("a", {"theta_start": 0.35})
t, _ = drive(a, 0.0, 50)
at_half = t
state = a.getFMUstate()
blob = a.serializeFMUstate(state)
_, first = drive(a, at_half, 30)
a.setFMUstate(state)
_, again = drive(a, at_half, 30)
restored = a.deSerializeFMUstate(blob)
a.setFMUstate(restored)
_, from_bytes = drive(a, at_half, 30)
fresh = fmu.instance("fresh", {"theta_start": 0.35})
fresh.setFMUstate(fresh.deSerializeFMUstate(blob))
_, fresh_run = drive(fresh, at_half, 30)
a.freeFMUstate(state)
a.freeFMUstate(restored)

# a state of another model (other parameters) is refused with a message, nothing changes
other = fmu.instance("other", {"theta_start": 0.2, "density": 2700.0})
fmu.messages.clear()
refused = False
try:
    other.setFMUstate(other.deSerializeFMUstate(blob))
except Exception:
    refused = True
refusal_logged = any("another model" in m for _, m in fmu.messages)

# two instances with different parameters, interleaved, against each alone
params_c = {"theta_start": 0.35}
params_d = {"theta_start": 0.2, "density": 2700.0, "youngs_modulus": 7e10, "omega_start": 0.5}
c, d = fmu.instance("c", params_c), fmu.instance("d", params_d)
tc = td = 0.0
inter_c, inter_d = [], []
for k in range(40):
    tc, oc = drive(c, tc, 1)
    td, od = drive(d, td, 1)
    inter_c += oc
    inter_d += od
_, alone_c = drive(fmu.instance("c2", params_c), 0.0, 40)
_, alone_d = drive(fmu.instance("d2", params_d), 0.0, 40)

report(first == again and first == from_bytes and first == fresh_run and refused and refusal_logged
       and inter_c == alone_c and inter_d == alone_d and inter_c != inter_d,
       state_time_s=at_half, steps_compared=len(first), serialized_bytes=len(blob),
       set_state_identical=first == again, deserialized_identical=first == from_bytes,
       fresh_instance_identical=first == fresh_run, foreign_state_refused=refused,
       refusal_logged=refusal_logged, instances_independent=inter_c == alone_c and inter_d == alone_d,
       theta_end_c=float.fromhex(inter_c[-1][0]), theta_end_d=float.fromhex(inter_d[-1][0]))
