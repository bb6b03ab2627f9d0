"""Test 1: `fmpy validate` finds no problem; `fmpy simulate` with theta_start = 0.35 rad and
tau = 0 reproduces the CLI's θ(t) within 1e-9 rad at every output point.

usage: validate_and_simulate.py FMU CLI_CSV CLI_ZERO_TORQUE_CSV

Both CSVs are the CLI's `results.csv` (`pendulum-fem run`): with its defaults (no torque term) and
with the zero torque declared as the FMU declares it. The FMU must be within
1e-9 rad of the first and bit-identical to the second."""

import sys

import numpy as np
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from fmu_common import report

fmu, cli, cli_torque = sys.argv[1], sys.argv[2], sys.argv[3]
problems = validate_fmu(fmu)
ref = np.genfromtxt(cli, delimiter=",", names=True)
ref_torque = np.genfromtxt(cli_torque, delimiter=",", names=True)
res = simulate_fmu(fmu, start_values={"theta_start": 0.35, "tau": 0.0}, stop_time=float(ref["time_s"][-1]),
                   output_interval=0.01, output=["theta", "omega", "gap", "total_energy"])
times_match = len(res) == len(ref) and float(np.max(np.abs(res["time"] - ref["time_s"]))) < 1e-12
err = float(np.max(np.abs(res["theta"] - ref["theta_rad"]))) if times_match else float("inf")
identical = bool(times_match and np.array_equal(res["theta"], ref_torque["theta_rad"]))
report(not problems and times_match and err <= 1e-9 and identical,
       problems=[str(p) for p in problems], rows=len(res), reference_rows=len(ref),
       max_theta_error_rad=err, bit_identical_to_cli_with_zero_torque=identical,
       energy_range_J=float(np.ptp(res["total_energy"])))
