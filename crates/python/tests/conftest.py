"""Shared fixtures: the CLI's results.csv of the default run and results.csv and events.csv of the
run with the rigid wall (made by the Rust test runner)."""

import csv
import os
from pathlib import Path

import pytest


def _read_csv(variable, what):
    """The CSV file named by the environment variable as (header, rows of strings)."""
    path = os.environ.get(variable)
    assert path, f"{variable} ({what}) is not set: run these tests through `cargo test --release --test suite python_package::`"
    with Path(path).open(newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = list(reader)
    return header, rows


@pytest.fixture(scope="session")
def cli_wall_results():
    """The CLI's `results.csv` for `run --set wall.kind="rigid" --set time.end=1` as (header, rows
    of floats), from PENDULUM_FEM_WALL_RESULTS_CSV."""
    header, rows = _read_csv("PENDULUM_FEM_WALL_RESULTS_CSV", "the CLI's results.csv with the wall")
    return header, [[float(x) for x in row] for row in rows]


@pytest.fixture(scope="session")
def cli_wall_events():
    """The CLI's `events.csv` of the same run as (header, rows: floats but the `event` column)."""
    header, rows = _read_csv("PENDULUM_FEM_WALL_EVENTS_CSV", "the CLI's events.csv with the wall")
    kinds = header.index("event")
    return header, [[x if j == kinds else float(x) for j, x in enumerate(row)] for row in rows]


@pytest.fixture(scope="session")
def cli_results():
    """The CLI's `results.csv` for `run --set time.end=1` as (header, rows of floats).

    tests/python_package.rs (the runner) writes it with the built `pendulum-fem` binary and passes
    its path in PENDULUM_FEM_RESULTS_CSV; without it the comparison fails (it never skips).
    """
    path = os.environ.get("PENDULUM_FEM_RESULTS_CSV")
    assert path, "PENDULUM_FEM_RESULTS_CSV is not set: run these tests through `cargo test --release --test suite python_package::`"
    with Path(path).open(newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = [[float(x) for x in row] for row in reader]
    return header, rows
