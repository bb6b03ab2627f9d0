"""pendulum_fem.sweep: the CLI's parameter study from Python, locally and on a Dask cluster.

Each table is compared with the `summary.csv` of `pendulum-fem sweep` for the same cases (the CLI
built by tests/python_package.rs, its path in PENDULUM_FEM_CLI), read with pandas.read_csv, every
column but wall_time_s (the one value that differs from one run to the next) compared exactly.
The cases are short default runs (time.end = 0.05).
"""

import os
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

import pendulum_fem

# a 3×2 grid: a list and a linear range
VARY = ["material.youngs_modulus=1e6,1e7,2.1e11", "initial.angle_deg=10:30:2"]
SHORT = {"time.end": 0.05}

# tests/sweep.rs's failing study: a configuration error and a solver failure between two good cases
FAILING_CASES = [
    {"initial.angle_deg": 10},
    {"material": {"youngs_modulus": -1}},
    {
        "solver.tolerance": 1e-300,
        "solver.max_iterations": 1,
        "solver.max_cutbacks": 0,
        "initial.elastic": "undeformed",
    },
    {"initial.angle_deg": 30},
]
FAILING_FILE = """set = ["time.end = 0.05"]

[[case]]
initial.angle_deg = 10

[[case]]
material.youngs_modulus = -1

[[case]]
solver.tolerance = 1e-300
solver.max_iterations = 1
solver.max_cutbacks = 0
initial.elastic = "undeformed"

[[case]]
initial.angle_deg = 30
"""


@pytest.fixture(scope="module")
def cli():
    """The `pendulum-fem` binary the runner built (never skipped when absent: a failure)."""
    path = os.environ.get("PENDULUM_FEM_CLI")
    assert path, "PENDULUM_FEM_CLI is not set: run these tests through `cargo test --release --test suite python_package::`"
    return path


def cli_sweep(cli, out: Path, *args: str) -> Path:
    """Runs `pendulum-fem sweep ARGS --out OUT` and returns OUT (a sweep with failed cases exits 1)."""
    env = {k: v for k, v in os.environ.items() if k not in ("SLURM_ARRAY_TASK_ID", "PBS_ARRAY_INDEX", "LSB_JOBINDEX")}
    done = subprocess.run(
        [cli, "sweep", "--quiet", "--no-plots", *args, "--out", str(out)],
        capture_output=True,
        text=True,
        env=env,
    )
    assert done.returncode in (0, 1) and (out / "summary.csv").exists(), done.stderr
    return out


def assert_same_table(got: pd.DataFrame, want: pd.DataFrame) -> None:
    """Equal column names, order, dtypes and values (exactly), but for wall_time_s."""
    assert list(got.columns) == list(want.columns)
    assert got["wall_time_s"].notna().all() and (got["wall_time_s"] > 0).all()
    pd.testing.assert_frame_equal(
        got.drop(columns="wall_time_s"), want.drop(columns="wall_time_s"), check_exact=True
    )


def without_wall_time(path: Path):
    """The lines of a summary without the wall_time_s field (no quoted fields in these tables)."""
    lines = [line.split(",") for line in path.read_text().splitlines()]
    c = lines[0].index("wall_time_s")
    return [cells[:c] + cells[c + 1 :] for cells in lines]


@pytest.fixture(scope="module")
def grid_cli(cli, tmp_path_factory):
    """The CLI's sweep of the 3×2 grid."""
    out = tmp_path_factory.mktemp("grid") / "cli"
    args = ["--set", "time.end=0.05"]
    for v in VARY:
        args += ["--vary", v]
    return cli_sweep(cli, out, *args)


def test_a_local_sweep_of_a_grid_equals_the_cli_summary(grid_cli, tmp_path):
    want = pd.read_csv(grid_cli / "summary.csv")
    assert len(want) == 6 and (want["status"] == "ok").all()
    out = tmp_path / "py"
    got = pendulum_fem.sweep(vary=VARY, config=SHORT, out=out, jobs=2)
    assert_same_table(got, want)
    assert list(got.columns[:2]) == ["material.youngs_modulus", "initial.angle_deg"]
    # the sweep folder as the CLI writes it: the case list, the summary, a folder per case
    assert (out / "cases.csv").read_text() == (grid_cli / "cases.csv").read_text()
    assert without_wall_time(out / "summary.csv") == without_wall_time(grid_cli / "summary.csv")
    for k in range(6):
        case = out / f"case-{k:04d}"
        assert (case / "results.csv").read_bytes() == (grid_cli / f"case-{k:04d}" / "results.csv").read_bytes()


def test_a_dask_local_cluster_returns_the_same_table(grid_cli):
    from dask.distributed import Client, LocalCluster

    want = pd.read_csv(grid_cli / "summary.csv")
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            got = pendulum_fem.sweep(vary=VARY, config=SHORT, client=client)
            # the cases ran on both workers' processes, not in this one
            assert len(client.scheduler_info()["workers"]) == 2
    assert_same_table(got, want)


def test_case_dicts_equal_the_cases_of_a_sweep_file_and_a_failed_case_is_a_row_with_its_message(cli, tmp_path):
    study = tmp_path / "study.toml"
    study.write_text(FAILING_FILE)
    want = pd.read_csv(cli_sweep(cli, tmp_path / "cli", "--file", str(study)) / "summary.csv")
    got = pendulum_fem.sweep(FAILING_CASES, config=SHORT)
    assert_same_table(got, want)
    assert list(got["status"]) == ["ok", "failed", "failed", "ok"]
    assert "material.youngs_modulus" in got["message"][1] and "allowed" in got["message"][1]
    assert "time step 1" in got["message"][2] and "Newton" in got["message"][2]
    assert list(got["final_time_s"][[0, 3]]) == [0.05, 0.05]


def test_a_case_with_an_unknown_key_fails_alone_and_names_the_key():
    got = pendulum_fem.sweep(
        [{"initial.angle_deg": 10}, {"material.youngs_modulu": 1e7}, {"initial.angle_deg": 30}], config=SHORT
    )
    assert list(got["status"]) == ["ok", "failed", "ok"]
    assert "youngs_modulu" in got["message"][1]
    assert got["final_time_s"][[0, 2]].tolist() == [0.05, 0.05] and pd.isna(got["final_time_s"][1])


def test_the_same_case_on_a_dask_worker_and_here_gives_the_same_row():
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            remote = pendulum_fem.sweep(FAILING_CASES, config=SHORT, client=client)
    here = pendulum_fem.sweep(FAILING_CASES, config=SHORT, jobs=1)
    assert_same_table(remote, here)


def test_nothing_to_vary_and_a_bad_vary_are_value_errors():
    with pytest.raises(ValueError, match="nothing to vary"):
        pendulum_fem.sweep(config=SHORT)
    with pytest.raises(ValueError, match="linear range"):
        pendulum_fem.sweep(vary="material.youngs_modulus=1:2")


def test_without_pandas_sweep_names_the_extra_to_install_before_running_a_case(monkeypatch, tmp_path):
    # None in sys.modules makes `import pandas` raise ImportError, as in an environment without it
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ModuleNotFoundError, match=r'pendulum-fem\[sweep\]') as error:
        pendulum_fem.sweep(vary="initial.angle_deg=10,20", config=SHORT, out=tmp_path / "study")
    assert error.value.name == "pandas"
    assert not (tmp_path / "study").exists(), "the error comes before anything is written"
