"""Simulates the FMU with fmpy and writes every output at every communication point as CSV.

usage: simulate_to_csv.py FMU OUT_CSV STOP_TIME STEP [NAME=VALUE ...]

The parameters NAME=VALUE are the FMU's start values (numbers). The CSV's header is `time` and
the outputs' names in the model description's order; reals are written with Python's `repr`
(the shortest text that reads back as the same double), integers and booleans as integers.
Used by `scripts/same-outputs` (its reduced FMU run) and by `tests/same_outputs.rs`."""

import sys

from fmpy import read_model_description, simulate_fmu

fmu, out, stop, step = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
md = read_model_description(fmu)
kinds = {v.name: v.type for v in md.modelVariables}
start = {}
for assignment in sys.argv[5:]:
    name, value = assignment.split("=", 1)
    start[name] = float(value) if kinds[name] in ("Real", "Float64") else int(value)
outputs = [v.name for v in md.modelVariables if v.causality == "output"]
result = simulate_fmu(fmu, start_values=start, stop_time=stop, output_interval=step, output=outputs)


def text(value):
    # numpy's float64 is a float; its int32 and bool_ are not
    return repr(float(value)) if isinstance(value, float) else str(int(value))


with open(out, "w") as f:
    f.write(",".join(["time"] + outputs) + "\n")
    for row in result:
        f.write(",".join(text(row[name]) for name in ["time"] + outputs) + "\n")
print(f"{len(result)} rows of {len(outputs)} outputs to {out}")
