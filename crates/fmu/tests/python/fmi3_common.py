"""Helpers of the FMI 3.0 test scripts: open PendulumFem3 with fmpy, capture its log messages, make
initialised co-simulation instances, read every output exactly."""

import atexit
import shutil
import tempfile

from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave


class Fmu3:
    """The FMI 3.0 FMU extracted once; `instance()` makes initialised co-simulation instances."""

    def __init__(self, path):
        self.md = read_model_description(path)
        self.dir = extract(path, unzipdir=tempfile.mkdtemp(prefix="pendulum-fmu3-"))
        atexit.register(shutil.rmtree, self.dir, True)
        self.vars = {v.name: v for v in self.md.modelVariables}
        outputs = [v for v in self.md.modelVariables if v.causality == "output"]
        self.floats = [v.valueReference for v in outputs if v.type == "Float64"]
        self.ints = [v.valueReference for v in outputs if v.type == "Int32"]
        self.bools = [v.valueReference for v in outputs if v.type == "Boolean"]
        self.messages = []

    def log(self, env, status, category, message):
        self.messages.append((status, message.decode("utf-8", "replace")))

    def instance(self, params, event_mode=True, early_return=True, name="pendulum3"):
        fmu = FMU3Slave(guid=self.md.guid, unzipDirectory=self.dir,
                        modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=name)
        fmu.instantiate(eventModeUsed=event_mode, earlyReturnAllowed=early_return, logMessage=self.log)
        fmu.enterInitializationMode(startTime=0.0)
        for k, v in params.items():
            vr = [self.vars[k].valueReference]
            {"Float64": lambda: fmu.setFloat64(vr, [float(v)]), "Int32": lambda: fmu.setInt32(vr, [int(v)]),
             "Boolean": lambda: fmu.setBoolean(vr, [bool(v)])}[self.vars[k].type]()
        fmu.exitInitializationMode()
        if event_mode:
            self.settle(fmu)
        return fmu

    @staticmethod
    def settle(fmu):
        """Event mode to step mode: fmi3UpdateDiscreteStates (must settle in one call), fmi3EnterStepMode."""
        need, terminate, _, _, defined, _ = fmu.updateDiscreteStates()
        assert not need and not terminate and not defined, "fmi3UpdateDiscreteStates did not settle in one call"
        fmu.enterStepMode()

    def outputs(self, fmu):
        """Every output, floats as their exact hex text."""
        return (tuple(x.hex() for x in fmu.getFloat64(self.floats)) + tuple(fmu.getInt32(self.ints))
                + tuple(bool(b) for b in fmu.getBoolean(self.bools)))
