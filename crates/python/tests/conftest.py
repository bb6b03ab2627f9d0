"""Shared fixtures: the CLI's results.csv of the default run (made by the Rust test runner)."""

import csv
import os
from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def cli_results():
    """The CLI's `results.csv` for `run --set time.end=1` as (header, rows of floats).

    tests/python_package.rs (the runner) writes it with the built `pendulum-fem` binary and passes
    its path in PENDULUM_FEM_RESULTS_CSV; without it the comparison fails (it never skips).
    """
    path = os.environ.get("PENDULUM_FEM_RESULTS_CSV")
    assert path, "PENDULUM_FEM_RESULTS_CSV is not set: run these tests through `cargo test --test python_package`"
    with Path(path).open(newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = [[float(x) for x in row] for row in reader]
    return header, rows
