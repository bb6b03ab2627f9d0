"""Real-time factor of the FMU driven by fmpy at communication steps of 10 ms and 1 ms (the
default pendulum, tau = 0 set every step, every output read every step), against the bare
stepper (`cargo run --release -p pendulum-fem-fmu --example stepper_speed`).

usage: python fmpy_speed.py target/fmu/PendulumFem.fmu [SIMULATED_SECONDS]"""

import sys
import time

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

path = sys.argv[1]
seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 2.0
md = read_model_description(path)
unzipped = extract(path)
vr = {v.name: v.valueReference for v in md.modelVariables}
reals = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
ints = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Integer"]
bools = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Boolean"]
for h in (0.01, 0.001):
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier="PendulumFem", instanceName="bench")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    steps = round(seconds / h)
    start = time.perf_counter()
    for k in range(steps):
        fmu.setReal([vr["tau"]], [0.0])
        fmu.doStep(currentCommunicationPoint=k * h, communicationStepSize=h)
        fmu.getReal(reals), fmu.getInteger(ints), fmu.getBoolean(bools)
    wall = time.perf_counter() - start
    print(f"FMU via fmpy h = {h} s: {steps} steps in {wall:.3f} s, real-time factor {seconds / wall:.2f} "
          f"({1e3 * wall / steps:.3f} ms/step)")
    fmu.terminate()
    fmu.freeInstance()
