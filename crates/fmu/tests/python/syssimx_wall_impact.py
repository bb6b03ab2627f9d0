"""Test 4 with the wall: syssimx's hybrid algorithm, rolling the FMU back through FMU states
(syssimx_pendulum.PendulumFMU), locates the impacts of the head on the rigid wall (wall_kind = 1,
theta_start = 20°, tau = 0) within 1e-4 s of the start times the CLI reports in events.csv.

The event indicator is the parity of the Integer output `contact_count` (+0.5 even, -0.5 odd):
a bounce inside one macro step leaves `gap` positive at both ends, but it changes the count. The
event is named `wall_hit`, which no FMU output is named (an output of the same name would hide the
event port). Macro step 0.01 s, run to 0.8 s: two impacts.

usage: syssimx_wall_impact.py FMU CLI_EVENTS_CSV"""

import csv
import os
import sys
import time

from syssimx import PortType, System
from syssimx.components.fmu import clear_extraction_cache
from syssimx.system.algorithms import HybridAlgorithm

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "python"))
from syssimx_pendulum import PendulumFMU  # noqa: E402

from fmu_common import Fmu, largest, report  # noqa: E402

path, events_csv = sys.argv[1], sys.argv[2]
THETA_START, DT, T_END, TOLERANCE = 0.3490658503988659, 0.01, 0.8, 1e-4

with open(events_csv, newline="") as f:
    starts = [float(row["time_s"]) for row in csv.DictReader(f) if row["event"] == "impact_start"]
starts = [t for t in starts if t < T_END]


def parity(component):
    """+0.5 after an even number of impacts, -0.5 after an odd one."""
    count = component.outputs["contact_count"].get()
    return 0.5 - (int(count or 0) % 2)


pendulum = PendulumFMU("pendulum", path)
pendulum.set_parameters(wall_kind=1, theta_start=THETA_START)
pendulum.add_event_indicator("wall_hit", parity, direction=0)
system = System("wall")
system.add_component(pendulum)
system.set_algorithm(HybridAlgorithm())
system.initialize(t0=0.0)
event_port = pendulum.output_specs["wall_hit"].type == PortType.EVENT
clock = time.perf_counter()
system.run(t0=0.0, tf=T_END, dt=DT)
seconds = time.perf_counter() - clock
located = [e.t for e in system.history.get_all_event_histories().get(("pendulum", "wall_hit"), [])]
final_count = int(pendulum.outputs["contact_count"].get())
pendulum.free()
clear_extraction_cache()

# the gap on the FMU's own trajectory at the CLI's first start time (CLI steps to 0.23 s, then one
# step onto it): how far the head still is from the wall at the reported touch
probe = Fmu(path)
slave = probe.instance(params={"wall_kind": 1, "theta_start": THETA_START})
t = 0.0
while t + DT < starts[0]:
    slave.doStep(t, DT)
    t = round(t + DT, 12)
slave.doStep(t, starts[0] - t)
gap_at_cli_start = slave.getReal([probe.vr("gap")])[0]
slave.terminate()
slave.freeInstance()

errors = [abs(a - b) for a, b in zip(located, starts)]
ok = event_port and len(starts) == 2 and len(located) == len(starts) and largest(errors) <= TOLERANCE and final_count == 2
report(ok, wall_hit_is_an_event_port=event_port, cli_impact_starts_s=starts, located_s=located, errors_s=errors, tolerance_s=TOLERANCE,
       contact_count_at_end=final_count, gap_at_cli_first_start_m=gap_at_cli_start, macro_step_s=DT,
       wall_seconds=seconds)
