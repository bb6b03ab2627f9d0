"""Parameter studies from Python: ``pendulum_fem.sweep``, locally or on a Dask cluster.

``sweep`` runs the cases of ``pendulum-fem sweep`` (the same grids, ``zip``, ``[[case]]`` lists,
configuration and overrides) one ``_core.run_case`` per case, and returns the study's summary as a
pandas DataFrame equal to the CLI's ``summary.csv`` read with ``pandas.read_csv`` (only
``wall_time_s`` differs from one run to the next):

>>> import pendulum_fem
>>> df = pendulum_fem.sweep(vary=["material.youngs_modulus=1e6,1e7", "initial.angle_deg=10:30:3"],
...                         config={"time.end": 0.5})

With a ``dask.distributed.Client`` the cases are the tasks of that cluster (a ``LocalCluster``,
or a Slurm, PBS or Kubernetes cluster through dask-jobqueue or dask-kubernetes); the workers need
this package installed (the same version). Without one, the cases run in a pool of ``jobs``
threads of this process (``run_case`` releases the GIL).
"""

from __future__ import annotations

import builtins
import io
import os
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from . import _core

__all__ = ["sweep"]

_Case = Tuple[List[Tuple[str, str]], List[str], Optional[str], Optional[str], int, bool]


def _run_one(varied, overrides, config, case_dir, threads, all_outputs) -> Dict[str, Any]:
    """One case (a Dask task): its summary row as a dict (see ``_core.run_case``)."""
    return _core.run_case(varied, overrides, config, case_dir, threads, all_outputs)


def _base(config, set) -> Tuple[Optional[str], List[str]]:
    """The base configuration file (absolute, so that workers find it on a shared file system) and
    the overrides of every case: a dict ``config`` and ``set`` (a dict or ``"key=value"`` strings)."""
    path: Optional[str] = None
    overrides: List[str] = []
    if isinstance(config, Mapping):
        overrides += _core.overrides_of(dict(config))
    elif config is not None:
        path = os.path.abspath(os.fspath(config))
    if isinstance(set, Mapping):
        overrides += _core.overrides_of(dict(set))
    elif set is not None:
        if isinstance(set, str):
            set = [set]
        overrides += [str(s) for s in set]
    return path, overrides


def _import_pandas():
    """pandas, or an ImportError that names the extra which installs it (before any case runs)."""
    try:
        import pandas
    except ImportError as e:
        raise ModuleNotFoundError(
            "pendulum_fem.sweep returns a pandas DataFrame and needs pandas: install the package's "
            '"sweep" extra, pip install "pendulum-fem[sweep]" (from a checkout: pip install '
            '"./crates/python[sweep]"; "dask" instead of "sweep" adds dask.distributed)',
            name="pandas",
        ) from e
    return pandas


def sweep(
    cases: Optional[Sequence[Mapping[str, Any]]] = None,
    *,
    vary: Optional[Union[str, Sequence[str]]] = None,
    zip: bool = False,
    config: Union[None, str, "os.PathLike[str]", Mapping[str, Any]] = None,
    set: Union[None, Sequence[str], Mapping[str, Any]] = None,
    out: Union[None, str, "os.PathLike[str]"] = None,
    client: Any = None,
    jobs: Optional[int] = None,
    threads: int = 1,
    all_outputs: bool = False,
):
    """Runs a parameter study and returns its summary as a pandas DataFrame.

    The cases are those of ``pendulum-fem sweep``: ``cases``, a list of dicts of configuration
    keys (nested sections or dotted keys; the ``[[case]]`` tables of a sweep file), then each
    ``vary`` (``"KEY=VALUES"``: a list ``1e6,1e7``, a linear range ``10:60:6`` or a log range
    ``1e6..2.1e11:8``), all as a grid or, with ``zip``, paired. Each case's configuration is
    ``config`` (a TOML file, a dict of keys like ``--set``, or the defaults), then ``set`` (a dict or
    ``"key=value"`` strings, the CLI's ``--set``), then the case's values; it writes only
    ``results.csv`` unless ``all_outputs``, which keeps the configuration's ``[output]`` switches
    for the CSV files; a case whose configuration asks for pictures or ParaView files fails with a
    message saying so (the package carries no plotting or image code; ``pendulum-fem sweep
    --all-outputs`` draws them).

    ``out``: the sweep folder (``out/case-NNNN/`` per case, ``cases.csv`` and ``summary.csv`` as
    the CLI writes them; on a cluster, a folder every worker sees); ``None`` keeps no files.
    ``client``: a ``dask.distributed.Client``; the cases are its tasks (``client.map``) and the
    rows come back with ``client.gather``. Without one they run here on ``jobs`` threads (default:
    the number of cores). ``threads``: threads per case (1, as the CLI's ``--threads``).

    A case that fails (a bad value or key, a solver failure) is a row with ``status == "failed"``
    and its ``message``; the others complete. The columns are the varied keys, the metrics
    (``final_time_s`` … ``energy_error``, ``impacts`` and ``contact_force_max_N`` when a wall is
    on), ``status`` and ``message``, with the dtypes ``pandas.read_csv`` gives ``summary.csv``.
    """
    pandas = _import_pandas()

    if isinstance(vary, str):
        vary = [vary]
    plan = _core.expand(list(vary or []), zip, None if cases is None else [dict(c) for c in cases])
    path, base_overrides = _base(config, set)
    if threads < 1:
        raise ValueError("sweep: threads must be >= 1")
    folder = None if out is None else os.path.abspath(os.fspath(out))
    if folder is not None:
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, "cases.csv"), "w", newline="") as f:
            f.write(plan["cases_csv"])
    args: List[_Case] = [
        (
            shown,
            base_overrides + overrides,
            path,
            None if folder is None else os.path.join(folder, f"case-{k:04d}"),
            threads,
            all_outputs,
        )
        for k, (shown, overrides) in enumerate(builtins.zip(plan["shown"], plan["overrides"]))
    ]
    if client is not None:
        columns = [list(c) for c in builtins.zip(*args)]
        futures = client.map(_run_one, *columns, pure=False)
        rows = client.gather(futures)
    else:
        workers = max(1, min(jobs or os.cpu_count() or 1, len(args)))
        with ThreadPoolExecutor(max_workers=workers) as pool:
            rows = list(pool.map(lambda a: _run_one(*a), args))
    text = _core.summary_csv(plan["keys"], rows)
    if folder is not None:
        with open(os.path.join(folder, "summary.csv"), "w", newline="") as f:
            f.write(text)
    return pandas.read_csv(io.StringIO(text))

