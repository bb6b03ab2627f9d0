"""Test 3: a second, independent importer (libcosim through libcosimpy, built on the FMI Library)
runs the FMU and agrees with fmpy: θ(t) with theta_start = 0.35 rad over 1 s at 10 ms steps.

usage: libcosimpy_agrees.py FMU"""

import sys

import numpy as np
from fmpy import simulate_fmu
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimObserver import CosimObserver
from libcosimpy.CosimSlave import CosimLocalSlave

from fmu_common import Fmu, report

path = sys.argv[1]
vr = Fmu(path).vr
STEPS, STEP_NS = 100, 10_000_000

execution = CosimExecution.from_step_size(step_size=STEP_NS)
observer = CosimObserver.create_last_value()
execution.add_observer(observer=observer)
index = execution.add_local_slave(local_slave=CosimLocalSlave(fmu_path=path, instance_name="pendulum"))
execution.real_initial_value(slave_index=index, variable_reference=vr("theta_start"), value=0.35)
theta = []
stepped = True
for _ in range(STEPS):
    stepped = stepped and execution.step()
    theta.append(observer.last_real_values(slave_index=index, variable_references=[vr("theta")])[0])
theta = np.array(theta)

res = simulate_fmu(path, start_values={"theta_start": 0.35}, stop_time=1.0, output_interval=0.01, output=["theta"])
fmpy_theta = res["theta"][1:]
err = float(np.max(np.abs(theta - fmpy_theta))) if len(theta) == len(fmpy_theta) else float("inf")
report(stepped and err <= 1e-12, steps=len(theta), max_difference_rad=err,
       bit_identical=bool(np.array_equal(theta, fmpy_theta)), theta_end=float(theta[-1]))
