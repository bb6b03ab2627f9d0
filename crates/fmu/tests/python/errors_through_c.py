"""FMI error paths through the C interface (fmpy): an invalid parameter fails
fmi2ExitInitializationMode with fmi2Error and a logged message naming the configuration key; a
failed step returns fmi2Error with a message naming the time and the cause and leaves the outputs
as they were; a communication point 1e-8 s off the FMU's time and a zero step are accepted.

usage: errors_through_c.py FMU"""

import sys

from fmpy.fmi2 import fmi2Error

from fmu_common import Fmu, report

fmu = Fmu(sys.argv[1])


def status_of(call):
    try:
        call()
        return 0
    except Exception as e:  # fmpy raises FMICallException carrying the status
        return getattr(e, "status", -1)


bad = fmu.instance("bad", initialize=False)
bad.setupExperiment(startTime=0.0)
bad.enterInitializationMode()
fmu.set(bad, {"poisson_ratio": 0.7})
fmu.messages.clear()
exit_status = status_of(bad.exitInitializationMode)
invalid_logged = any("material.poisson_ratio" in m for _, m in fmu.messages)

weak = fmu.instance("weak", {"solver_max_iterations": 1, "solver_max_cutbacks": 0})
before = fmu.outputs(weak)
fmu.messages.clear()
# the first internal step converges in one Newton iteration, a later one does not: the whole
# communication step is rolled back
step_status = status_of(lambda: weak.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.03))
failure = [m for _, m in fmu.messages]
failure_named = any("from t = 0 s" in m and "Newton" in m for m in failure)
unchanged = fmu.outputs(weak) == before

ok_inst = fmu.instance("ok", {"theta_start": 0.35})
ok_inst.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.01)
off_status = status_of(lambda: ok_inst.doStep(currentCommunicationPoint=0.01 + 1e-8, communicationStepSize=0.0))
step_after = status_of(lambda: ok_inst.doStep(currentCommunicationPoint=0.01 - 1e-8, communicationStepSize=0.01))

report(exit_status == fmi2Error and invalid_logged and step_status == fmi2Error and failure_named and unchanged
       and off_status == 0 and step_after == 0,
       exit_status=exit_status, invalid_logged=invalid_logged, step_status=step_status,
       failure_message=failure[-1] if failure else None, outputs_unchanged=unchanged,
       zero_step_off_by_1e8=off_status, step_off_by_1e8=step_after)
