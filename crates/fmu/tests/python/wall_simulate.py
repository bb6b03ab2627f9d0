"""Test 1 with the wall: `fmpy simulate` with wall_kind = 1 (rigid), theta_start = 20° and tau = 0
reproduces the CLI's θ(t), gap, contact force and impact count at every output point.

usage: wall_simulate.py FMU CLI_CSV CLI_ZERO_TORQUE_CSV

Both CSVs are the CLI's `results.csv` (`pendulum-fem run --set wall.kind="rigid"`; the columns
`time_s,theta_rad,gap_m,contact_force_N,impacts` are read), without a torque term and with the zero
torque declared as the FMU declares it. The FMU must be within 1e-9 rad (θ) and 1e-12 m (gap) of the first and
bit-identical to the second (θ, gap, force); its contact_count equals the CLI's impacts."""

import sys

import numpy as np
from fmpy import simulate_fmu

from fmu_common import report

fmu, cli, cli_torque = sys.argv[1], sys.argv[2], sys.argv[3]
ref = np.genfromtxt(cli, delimiter=",", names=True)
ref_torque = np.genfromtxt(cli_torque, delimiter=",", names=True)
res = simulate_fmu(fmu, start_values={"theta_start": 0.3490658503988659, "wall_kind": 1, "tau": 0.0},
                   stop_time=float(ref["time_s"][-1]), output_interval=0.01,
                   output=["theta", "gap", "contact_force", "contact_count", "impact"])
times_match = len(res) == len(ref) and float(np.max(np.abs(res["time"] - ref["time_s"]))) < 1e-12
if times_match:
    theta_err = float(np.max(np.abs(res["theta"] - ref["theta_rad"])))
    gap_err = float(np.max(np.abs(res["gap"] - ref["gap_m"])))
else:
    theta_err = gap_err = float("inf")
identical = bool(times_match and all(np.array_equal(res[a], ref_torque[b]) for a, b in
                                     (("theta", "theta_rad"), ("gap", "gap_m"), ("contact_force", "contact_force_N"))))
counts = bool(times_match and np.array_equal(res["contact_count"], ref_torque["impacts"]))
# `impact` is true exactly in the output steps in which the count went up
went_up = np.concatenate([[False], np.diff(res["contact_count"]) > 0])
impact_flags = bool(np.array_equal(res["impact"].astype(bool), went_up))
impacts = int(res["contact_count"][-1])
report(times_match and theta_err <= 1e-9 and gap_err <= 1e-12 and identical and counts and impact_flags
       and impacts >= 2, rows=len(res), reference_rows=len(ref), max_theta_error_rad=theta_err,
       max_gap_error_m=gap_err, bit_identical_to_cli_with_zero_torque=identical,
       contact_count_equals_cli_impacts=counts, impact_flags_match=impact_flags, impacts=impacts,
       min_gap_m=float(np.min(res["gap"])), max_contact_force_N=float(np.max(res["contact_force"])))
