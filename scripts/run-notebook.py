"""Executes one Jupyter notebook with nbclient in the current folder and fails on any error.

    python run-notebook.py NOTEBOOK.ipynb EXECUTED.ipynb

The kernel is this interpreter's (ipykernel's `python3`), its working folder the current one; a
cell that raises stops the run with the cell's traceback and a non-zero exit status, and so does a
notebook that draws no figure (matplotlib's inline backend puts them in the outputs). The executed
notebook (with its outputs) is written to EXECUTED.ipynb for inspection. Used by tests/notebooks.rs.
"""

import sys
import time

import nbformat
from nbclient import NotebookClient

source, executed = sys.argv[1], sys.argv[2]
nb = nbformat.read(source, as_version=4)
start = time.perf_counter()
try:
    NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": "."}}).execute()
finally:
    nbformat.write(nb, executed)
errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []) if o.output_type == "error"]
assert not errors, f"{source}: error outputs {errors}"
code = [c for c in nb.cells if c.cell_type == "code"]
assert all(c.execution_count is not None for c in code), f"{source}: a code cell did not run"
figures = sum("image/png" in o.get("data", {}) for c in code for o in c.outputs)
assert figures > 0, f"{source}: no figure in the outputs"
print(f"{len(code)} code cells ran in {time.perf_counter() - start:.1f} s, {figures} figures")
