"""Real-time factor of the FMU driven by fmpy at communication steps of 10 ms and 1 ms (the
default pendulum, tau = 0 set every step, every output read every step), against the bare
stepper (`cargo run --release -p pendulum-fem-fmu --example stepper_speed`). Best of REPEATS
runs, wall and CPU time (all threads of the process).

With MODEL_KIND = 1 the FMU runs its reduced body (parameter `model_kind`; default 0, the full one);
WALL_KIND (parameter `wall_kind`: 0 none, the default, 1 rigid, 2 deformable) puts the wall in the
swing, which the default pendulum from 20° strikes twice a period.

usage: python fmpy_speed.py target/fmu/PendulumFem.fmu [SIMULATED_SECONDS [REPEATS [MODEL_KIND [WALL_KIND]]]]"""

import shutil
import sys
import time

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

path = sys.argv[1]
seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 2.0
repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 3
model_kind = int(sys.argv[4]) if len(sys.argv) > 4 else 0
wall_kind = int(sys.argv[5]) if len(sys.argv) > 5 else 0
md = read_model_description(path)
unzipped = extract(path)
vr = {v.name: v.valueReference for v in md.modelVariables}
reals = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
ints = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Integer"]
bools = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Boolean"]
for h in (0.01, 0.001):
    steps = round(seconds / h)
    best_wall = best_cpu = float("inf")
    for _ in range(repeats):
        fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier="PendulumFem", instanceName="bench")
        fmu.instantiate()
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.setInteger([vr["model_kind"], vr["wall_kind"]], [model_kind, wall_kind])
        fmu.exitInitializationMode()
        start, cpu = time.perf_counter(), time.process_time()
        for k in range(steps):
            fmu.setReal([vr["tau"]], [0.0])
            fmu.doStep(currentCommunicationPoint=k * h, communicationStepSize=h)
            fmu.getReal(reals), fmu.getInteger(ints), fmu.getBoolean(bools)
        best_wall = min(best_wall, time.perf_counter() - start)
        best_cpu = min(best_cpu, time.process_time() - cpu)
        # the master's own cost: the same calls without a step (the outputs are kept between steps)
        t_calls = time.process_time()
        for k in range(steps):
            fmu.setReal([vr["tau"]], [0.0])
            fmu.doStep(currentCommunicationPoint=steps * h, communicationStepSize=0.0)
            fmu.getReal(reals), fmu.getInteger(ints), fmu.getBoolean(bools)
        calls = time.process_time() - t_calls
        fmu.terminate()
        fmu.freeInstance()
    wall = ["", ", rigid wall", ", deformable wall"][wall_kind]
    print(f"FMU via fmpy{' (reduced body)' if model_kind else ''}{wall} h = {h} s: {steps} steps, best of {repeats}: wall {best_wall:.3f} s (real-time factor "
          f"{seconds / best_wall:.2f}, {1e3 * best_wall / steps:.3f} ms/step), CPU {best_cpu:.2f} s; "
          f"the calls alone (zero steps): CPU {calls:.2f} s")

shutil.rmtree(unzipped, ignore_errors=True)
