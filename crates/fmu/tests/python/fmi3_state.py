"""FMI 3.0 FMU states replay bit for bit, across an early return at an impact.

usage: fmi3_state.py FMU3

With the rigid wall, event mode and early return: step by 0.05 s to the first impact's early
return; take the FMU state there (with the continuation of the interrupted internal step) and
serialise it; go on to 0.6 s through the event mode, recording every output at every point. Then
(a) set the state on the same instance and (b) deserialise it into a second instance and set it
there: both replays give the same outputs bit for bit."""

import sys

from fmi3_common import Fmu3
from fmu_common import report

f = Fmu3(sys.argv[1])
PARAMS = {"theta_start": 0.3490658503988659, "wall_kind": 1}
STEP, STOP = 0.05, 0.6


def run_from(fmu, t, event_first):
    """Steps from t to STOP, handling events as fmpy does; returns [(t, outputs)]."""
    rows = []
    if event_first:
        fmu.enterEventMode()
        f.settle(fmu)
        rows.append((t, f.outputs(fmu)))
    k = round(t / STEP - 0.5) + 1 if abs(t / STEP - round(t / STEP)) > 1e-9 else round(t / STEP) + 1
    while t < STOP - 1e-12:
        target = k * STEP
        event, terminate, early, last = fmu.doStep(t, target - t)
        t = last if early else target
        rows.append((t, f.outputs(fmu)))
        if event:
            fmu.enterEventMode()
            f.settle(fmu)
            rows.append((t, f.outputs(fmu)))
        if not early:
            k += 1
    return rows


fmu = f.instance(PARAMS)
t, k = 0.0, 1
while True:
    event, terminate, early, last = fmu.doStep(t, k * STEP - t)
    if early:
        t = last
        break
    t = k * STEP
    k += 1
    assert t < 0.5, "no early return before 0.5 s"
state = fmu.getFMUState()
blob = fmu.serializeFMUState(state)
first = run_from(fmu, t, event)

fmu.setFMUState(state)
replay = run_from(fmu, t, event)

other = f.instance(PARAMS, name="second")
other.setFMUState(other.deserializeFMUState(blob))
replay2 = run_from(other, t, event)
count_after = first[-1][1][f.floats.__len__()]

ok = replay == first and replay2 == first and len(first) >= 8 and count_after >= 1
report(ok, early_return_s=t, points=len(first), state_bytes=len(blob), replay_identical=replay == first,
       deserialized_replay_identical=replay2 == first, contact_count_at_end=count_after,
       errors=[m for s, m in f.messages if s >= 3])
