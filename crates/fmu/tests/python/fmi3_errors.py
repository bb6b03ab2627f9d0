"""FMI 3.0 functions this Co-Simulation FMU does not offer answer fmi3Error and log the reason.

usage: fmi3_errors.py FMU3

fmi3GetContinuousStates (Model Exchange), fmi3GetFloat32 of a value reference (no Float32
variables), fmi3EnterEventMode on an instance made with eventModeUsed = false, and
fmi3InstantiateModelExchange (null, logged). After the refusals the instance still steps: θ
leaves its start, and every output equals, bit for bit, the same step of a fresh instance."""

import ctypes
import math
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

# the instance still works after the refusals: its step moves θ off the start and gives every
# output exactly as the same step of an instance that was never refused anything
theta_vr = [f.vars["theta"].valueReference]
theta_start = fmu.getFloat64(theta_vr)[0]
fmu.doStep(0.0, 0.01)
theta = fmu.getFloat64(theta_vr)[0]
untouched = f.instance({}, event_mode=False, early_return=False, name="untouched")
untouched.doStep(0.0, 0.01)
same_as_untouched = f.outputs(fmu) == f.outputs(untouched)
moved = math.isfinite(theta) and theta != theta_start

ok = (me_status == ERROR and any("fmi3GetContinuousStates" in m and "Co-Simulation only" in m for m in me_log)
      and f32_status == ERROR and any("fmi3GetFloat32" in m and "value reference 1" in m for m in f32_log)
      and ev_status == ERROR and any("eventModeUsed = false" in m for m in ev_log)
      and not null and any("fmi3InstantiateModelExchange" in m for m in me_inst_log)
      and moved and same_as_untouched)
report(ok, statuses=[me_status, f32_status, ev_status], null_model_exchange_instance=not null,
       messages=me_log + f32_log + ev_log + me_inst_log, theta_start=theta_start, theta_after=theta,
       step_moved_theta=moved, outputs_equal_an_untouched_instance=same_as_untouched)
