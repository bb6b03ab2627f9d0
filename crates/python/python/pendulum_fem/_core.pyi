"""Type stubs of the Rust extension module ``pendulum_fem._core`` (re-exported by ``pendulum_fem``)."""

import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str


class ConvergenceError(RuntimeError):
    """A time step (or the initial equilibrium) failed after every cut-back, or reached a state
    with a NaN or an infinity; the simulation is left exactly as before the call."""


class OutsideModelError(RuntimeError):
    """A time step leads outside what the model covers (the message names the cause and what to
    change); the simulation is left exactly as before the call."""


class UnknownKeyError(KeyError, ValueError):
    """A configuration key that names nothing: ``key`` is the dotted key, ``allowed`` the keys
    allowed where it fails (the section's, or the sections at the top level). A ``KeyError`` and a
    ``ValueError``, so either ``except`` catches it."""

    key: Optional[str]
    allowed: List[str]

    def __init__(self, message: str, key: Optional[str] = None, allowed: Sequence[str] = ()) -> None: ...

def csv_columns(wall: bool = False) -> List[str]:
    """The header of ``results.csv``: the column names of :meth:`Simulation.run`; with
    ``wall=True`` those of a model with a wall (``gap_m``, ``contact_force_N``, ``contact_J``,
    ``impacts`` at the end)."""

def event_columns() -> List[str]:
    """The header of ``events.csv``: the keys of the rows of :attr:`Simulation.events`."""

def internal_steps(h: float, max_step: float, last: Optional[float] = None) -> Tuple[int, float]:
    """``(n, step)``: a communication step ``h`` [s] as ``n`` internal steps of
    ``step <= max_step`` [s], by the FMU's rule: a multiple of ``max_step`` (to 1e-9 relative)
    takes steps of exactly ``max_step``, any other ``h`` ``ceil(h / max_step)`` equal steps, and
    an internal step within 1e-9 of ``last`` (the previous communication step's) is taken as
    ``last``. Raises ``ValueError`` (naming the values) for an ``h`` or ``max_step`` that is not
    finite and positive, or when more than a million internal steps would be needed."""

class Simulation:
    """A deformable pendulum simulation (finite elements, hyperelastic, on a hinge under gravity).

    ``config`` is a TOML file (path), a dict of the CLI's configuration keys (nested sections or
    dotted keys) or ``None`` for the defaults (the tutorial's steel pendulum released at 20°).
    Keyword overrides use the same keys and win over ``config``::

        Simulation("pendulum.toml", time={"dt": 0.005})
        Simulation({"material": {"youngs_modulus": 1e7}})
        Simulation(**{"material.youngs_modulus": 1e7, "initial.angle_deg": 45})

    A value of ``None`` leaves a key as it is. An unknown key raises :class:`UnknownKeyError` (a
    ``KeyError`` and a ``ValueError``) naming it and the keys allowed there; bad values raise
    ``ValueError`` with the library's message listing every mistake, each naming its key
    (``pendulum-fem init`` writes every key with its unit); a file that cannot be read raises its
    ``OSError`` (``FileNotFoundError``). A key given that has no effect here (``torque.amplitude``
    without a torque profile, the ``[output]`` keys, which a Simulation does not write) raises a
    ``UserWarning`` naming it and what would make it act.
    """

    def __init__(self, config: Union[str, "os.PathLike[str]", Mapping[str, Any], None] = None, **overrides: Any) -> None: ...
    def step(self, dt: float) -> int:
        """Advances by ``dt`` [s] (any finite ``dt > 0``; the GIL is released) and returns the
        Newton iterations of the step. ``n`` calls with the same ``dt`` land on ``t0 + n·dt``
        exactly. A failed step raises :class:`ConvergenceError` and changes nothing."""
    def step_to(self, t_end: float) -> int:
        """Advances by one step that lands exactly on ``t_end`` [s] (after the current time)."""
    def run(self, end: float, dt: Optional[float] = None) -> Dict[str, npt.NDArray[np.float64]]:
        """Runs from the current state to ``end`` [s] in steps of ``dt`` (default ``time.dt``; a
        shorter last step lands on ``end``) and returns the rows of ``results.csv`` as numpy
        columns named as its header (:func:`csv_columns`; with a wall, the contact columns too),
        the current state first. From the start this equals the CLI's ``results.csv`` for
        ``time.end = end`` bit for bit. The GIL is released; Ctrl-C stops at a step boundary."""
    def snapshot(self) -> bytes:
        """The complete state as bytes; :meth:`restore` continues bit for bit."""
    def restore(self, data: bytes) -> None:
        """Restores a :meth:`snapshot` of a simulation of the same model (else ``ValueError``)."""
    def __reduce__(self) -> Tuple[Any, Tuple[str, bytes]]: ...
    @staticmethod
    def _from_state(config_toml: str, snapshot: bytes) -> "Simulation": ...
    @property
    def error_estimate(self) -> Optional[Tuple[float, float]]:
        """A reduced body's largest error estimate so far and its time ``(eta, t)``: the relative
        error of its elastic forces against the full model's; above 0.01 it warns once (a
        ``UserWarning``). ``None`` for the full model."""
    @property
    def time(self) -> float:
        """Time of the current state [s]."""
    @property
    def theta(self) -> float:
        """Proxy angle [rad]: the best-fit rotation about the pivot, counter-clockwise from
        hanging down, unwrapped past ±π."""
    @property
    def omega(self) -> float:
        """Best-fit angular velocity [rad/s]."""
    @property
    def alpha(self) -> float:
        """Best-fit angular acceleration [rad/s²]; it follows ``tau`` at once."""
    @property
    def tau(self) -> float:
        """Pivot torque [N m], counter-clockwise positive (held value, else the ``[torque]``
        profile's value now, 0 without one). Setting it holds the value over the following steps.
        A model without a torque profile gets a torque input when ``tau`` is first set, which must
        happen before its first step (or declare it: ``Simulation(torque={"profile": "constant"})``)."""
    @tau.setter
    def tau(self, value: float) -> None: ...
    @property
    def gap(self) -> float:
        """Gap between the head and the wall face [m], positive while apart. With a wall
        (``wall.kind = "rigid"``) the stepper's smallest gap of the head's arc to the face
        (negative: the largest penetration; the ``gap_m`` column); without one the head's distance
        to the plane ``x = wall.x`` (``inf`` for a mesh without a head)."""
    @property
    def contact_force(self) -> float:
        """Normal force of the wall on the head [N] (``contact_force_N``; 0 without a wall)."""
    @property
    def impacts(self) -> int:
        """Impacts of the head on the wall so far, counted at the first penetration (``impacts``).
        Its parity is the event indicator for a co-simulation master: an impact may start and end
        between two communication points."""
    @property
    def in_contact(self) -> bool:
        """Whether the head is in an impact now."""
    @property
    def events(self) -> List[Dict[str, Union[float, str]]]:
        """The contact events so far, the rows of the CLI's ``events.csv`` as dicts keyed by its
        header (:func:`event_columns`): ``time_s``, ``event`` (``"impact_start"`` or
        ``"impact_end"``), ``theta_rad``, ``omega_rad_s``, ``impulse_N_s``, ``max_penetration_m``, ``max_force_N``.
        Empty without a wall."""
    @property
    def energies(self) -> Dict[str, float]:
        """``kinetic``, ``strain``, ``gravity``, ``contact`` (the wall's, 0 without one), ``total``
        (their sum) and ``torque_work`` [J]."""
    @property
    def hinge_reaction(self) -> Tuple[float, float]:
        """Force of the hinge on the body ``(fx, fy)`` [N]."""
    @property
    def steps(self) -> int:
        """Steps taken since the start."""
    @property
    def newton_iterations(self) -> int:
        """Newton iterations of the last step."""
    @property
    def nodes(self) -> npt.NDArray[np.float64]:
        """Reference node coordinates, shape ``(nodes, 2)`` [m]; pivot at the origin."""
    @property
    def triangles(self) -> npt.NDArray[np.int64]:
        """Six-node triangles as node indices, shape ``(triangles, 6)``."""
    @property
    def displacement(self) -> npt.NDArray[np.float64]:
        """Nodal displacement, shape ``(nodes, 2)`` [m] (a copy)."""
    @property
    def velocity(self) -> npt.NDArray[np.float64]:
        """Nodal velocity, shape ``(nodes, 2)`` [m/s] (a copy)."""
    @property
    def von_mises(self) -> npt.NDArray[np.float64]:
        """Nodal von Mises stress, shape ``(nodes,)`` [Pa] (computed on access)."""
    @property
    def cauchy_stress(self) -> npt.NDArray[np.float64]:
        """Nodal Cauchy stress ``[σxx, σyy, σxy]``, shape ``(nodes, 3)`` [Pa] (computed on access)."""
    @property
    def mass(self) -> float:
        """Mass of the body [kg]."""
    @property
    def inertia(self) -> float:
        """Moment of inertia about the pivot [kg m²]."""
    @property
    def center_of_mass(self) -> Tuple[float, float]:
        """Centre of mass of the hanging body ``(x, y)`` [m], pivot at the origin."""
    @property
    def config(self) -> Dict[str, Any]:
        """The configuration in effect, as a dict of sections."""
    @property
    def config_toml(self) -> str:
        """The configuration in effect as TOML (for ``pendulum-fem run --config``)."""

# Parameter studies (src/study.rs; used by pendulum_fem.sweep)

def expand(
    vary: List[str] = ..., zip: bool = False, cases: Optional[List[Dict[str, Any]]] = None
) -> Dict[str, Any]:
    """The cases of a study as ``pendulum-fem sweep`` makes them (``cases`` first, then each
    ``vary``; a grid or, with ``zip``, paired): ``keys``, ``shown`` (per case, ``(key, value)`` as in
    the summary), ``overrides`` (per case, ``key=value``) and ``cases_csv``."""

def overrides_of(config: Dict[str, Any]) -> List[str]:
    """A dict of configuration keys as the CLI's ``--set key=value`` overrides."""

def run_case(
    varied: List[Tuple[str, str]],
    overrides: List[str],
    config: Union[None, str, os.PathLike[str]] = None,
    case_dir: Union[None, str, os.PathLike[str]] = None,
    threads: int = 1,
    all_outputs: bool = False,
) -> Dict[str, Any]:
    """Runs one case as ``pendulum-fem sweep`` does (without the GIL) and returns its summary row
    (column → value; ``None`` for an empty cell); a failed case is ``status == "failed"``."""

def summary_csv(keys: List[str], rows: List[Dict[str, Any]]) -> str:
    """The text of the CLI's ``summary.csv`` for the varied ``keys`` and the rows of :func:`run_case`."""
