"""FMI 3.0 functions this Co-Simulation FMU does not offer answer fmi3Error and log the reason.

usage: fmi3_errors.py FMU3

fmi3GetContinuousStates (Model Exchange), fmi3GetFloat32 of a value reference (no Float32
variables), fmi3EnterEventMode on an instance made with eventModeUsed = false, and
fmi3InstantiateModelExchange (null, logged)."""

import ctypes
import sys

from fmpy.fmi3 import fmi3Float64, fmi3Float32, fmi3ValueReference

from fmi3_common import Fmu3
from fmu_common import report

f = Fmu3(sys.argv[1])
fmu = f.instance({}, event_mode=False, early_return=False)
lib = fmu.dll
ERROR = 3


def call(name, *args):
    fn = getattr(lib, name)
    fn.restype = ctypes.c_int
    before = len(f.messages)
    status = fn(fmu.component, *args)
    logged = [m for s, m in f.messages[before:] if s == ERROR]
    return status, logged


x = (fmi3Float64 * 4)()
me_status, me_log = call("fmi3GetContinuousStates", x, ctypes.c_size_t(4))
vr = (fmi3ValueReference * 1)(1)
f32 = (fmi3Float32 * 1)()
f32_status, f32_log = call("fmi3GetFloat32", vr, ctypes.c_size_t(1), f32, ctypes.c_size_t(1))
ev_status, ev_log = call("fmi3EnterEventMode")

inst_me = lib.fmi3InstantiateModelExchange
inst_me.restype = ctypes.c_void_p
before = len(f.messages)
null = inst_me(b"me", f.md.guid.encode(), b"", ctypes.c_bool(False), ctypes.c_bool(False), None, fmu.logMessage)
me_inst_log = [m for s, m in f.messages[before:] if s == ERROR]

# the instance still works after the refusals
fmu.doStep(0.0, 0.01)
theta = fmu.getFloat64([f.vars["theta"].valueReference])[0]

ok = (me_status == ERROR and any("fmi3GetContinuousStates" in m and "Co-Simulation only" in m for m in me_log)
      and f32_status == ERROR and any("fmi3GetFloat32" in m and "value reference 1" in m for m in f32_log)
      and ev_status == ERROR and any("eventModeUsed = false" in m for m in ev_log)
      and not null and any("fmi3InstantiateModelExchange" in m for m in me_inst_log) and theta == theta)
report(ok, statuses=[me_status, f32_status, ev_status], null_model_exchange_instance=not null,
       messages=me_log + f32_log + ev_log + me_inst_log, theta_after=theta)
