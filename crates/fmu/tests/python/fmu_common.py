"""Helpers shared by the FMU test scripts: open the FMU with fmpy, capture its log messages,
drive an instance step by step, and report a result as one JSON line on stdout."""

import atexit
import json
import math
import shutil
import sys
import tempfile

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, defaultCallbacks


class Fmu:
    """The FMU extracted once; `instance()` makes initialised slaves."""

    def __init__(self, path):
        self.path = path
        self.md = read_model_description(path)
        self.dir = extract(path, unzipdir=tempfile.mkdtemp(prefix="pendulum-fmu-"))
        atexit.register(shutil.rmtree, self.dir, True)
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.reals = [v.name for v in self.md.modelVariables if v.causality == "output" and v.type == "Real"]
        self.ints = [v.name for v in self.md.modelVariables if v.causality == "output" and v.type == "Integer"]
        self.bools = [v.name for v in self.md.modelVariables if v.causality == "output" and v.type == "Boolean"]
        self.messages = []

    def vr(self, name):
        return self.vars[name].valueReference

    def callbacks(self):
        """Callbacks whose logger appends (status, message) to self.messages."""
        cb = fmi2CallbackFunctions()

        def log(env, instance, status, category, message):
            self.messages.append((status, message.decode("utf-8", "replace")))

        self._keep = fmi2CallbackLoggerTYPE(log)
        cb.logger = self._keep
        cb.allocateMemory = defaultCallbacks.allocateMemory
        cb.freeMemory = defaultCallbacks.freeMemory
        try:
            from fmpy.logging import addLoggerProxy
            from ctypes import byref

            addLoggerProxy(byref(cb))
        except Exception as e:  # the proxy formats the variadic message; without it the text is "%s"
            raise RuntimeError(f"fmpy logger proxy unavailable: {e}")
        return cb

    def instance(self, name="pendulum", params=None, initialize=True):
        """A slave with `params` (name -> value) applied in initialisation mode."""
        fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.dir,
                        modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=name)
        fmu.instantiate(callbacks=self.callbacks())
        if initialize:
            fmu.setupExperiment(startTime=0.0)
            fmu.enterInitializationMode()
            self.set(fmu, params or {})
            fmu.exitInitializationMode()
        return fmu

    def set(self, fmu, params):
        for k, v in params.items():
            t = self.vars[k].type
            if t == "Real":
                fmu.setReal([self.vr(k)], [float(v)])
            elif t == "Integer":
                fmu.setInteger([self.vr(k)], [int(v)])
            else:
                fmu.setBoolean([self.vr(k)], [bool(v)])

    def outputs(self, fmu):
        """Every output as a tuple (reals, then integers, then booleans)."""
        r = fmu.getReal([self.vr(n) for n in self.reals])
        i = fmu.getInteger([self.vr(n) for n in self.ints])
        b = fmu.getBoolean([self.vr(n) for n in self.bools])
        return tuple(r) + tuple(i) + tuple(bool(x) for x in b)

    def close(self):
        shutil.rmtree(self.dir, ignore_errors=True)


def report(ok, **figures):
    """One JSON line for the Rust test; exit code 0 only when ok."""
    print(json.dumps({"ok": bool(ok), **figures}))
    sys.exit(0 if ok else 1)


def largest(values):
    """The largest of `values`, NaN when any is NaN (the built-in `max` drops a NaN that is not
    first, so a bound checked on it would pass); inf for none."""
    values = [float(v) for v in values]
    if any(math.isnan(v) for v in values):
        return float("nan")
    return max(values, default=float("inf"))


def bits(values):
    """Exact representation of a tuple of outputs (floats as hex)."""
    return tuple(v.hex() if isinstance(v, float) else v for v in values)
