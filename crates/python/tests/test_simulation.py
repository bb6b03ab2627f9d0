"""The Python package: configuration, stepping, results, state and errors (issue 11, test 5)."""

import math
import os
import pickle
import subprocess
import sys
import threading
import warnings

import numpy as np
import pytest

import pendulum_fem
from pendulum_fem import ConvergenceError, OutsideModelError, Simulation


def bits(a):
    """The IEEE bits of a float array (equal bits: bit-identical values, NaNs included)."""
    return np.ascontiguousarray(np.asarray(a, dtype=np.float64)).view(np.int64)


def state_of(sim):
    """Everything observable about a state, as bits."""
    e = sim.energies
    scalars = [sim.time, sim.theta, sim.omega, sim.alpha, sim.tau, sim.gap] + [e[k] for k in sorted(e)]
    return np.concatenate([bits(scalars), bits(sim.displacement).ravel(), bits(sim.velocity).ravel()])


def test_run_equals_the_cli_results_csv_bit_for_bit(cli_results):
    header, rows = cli_results
    result = Simulation().run(1.0, 0.01)
    assert list(result) == header == pendulum_fem.csv_columns()
    expected = np.array(rows)
    assert len(result["time_s"]) == len(rows) == 101
    for j, name in enumerate(header):
        got = result[name]
        assert got.dtype == np.float64 and got.shape == (101,)
        differ = np.flatnonzero(bits(got) != bits(expected[:, j]))
        assert differ.size == 0, f"{name}: first difference at row {differ[0]}: {got[differ[0]]!r} != {expected[differ[0], j]!r}"


def test_run_continues_from_the_current_state_and_lands_on_end():
    sim = Simulation()
    sim.step(0.01)
    rows = sim.run(0.035, 0.01)
    assert rows["time_s"][0] == 0.01
    assert rows["time_s"][-1] == 0.035 == sim.time
    assert len(rows["time_s"]) == 4  # 0.01, 0.02, 0.03, 0.035


def test_snapshot_and_restore_continue_bit_for_bit():
    sim = Simulation()
    for _ in range(10):
        sim.step(0.01)
    snap = sim.snapshot()
    assert isinstance(snap, bytes)
    for _ in range(10):
        sim.step(0.01)
    first = state_of(sim)
    sim.restore(snap)
    assert sim.time == pytest.approx(0.1, abs=1e-15)
    for _ in range(10):
        sim.step(0.01)
    assert np.array_equal(state_of(sim), first)
    assert sim.snapshot() == Simulation._from_state(sim.config_toml, sim.snapshot()).snapshot()


def test_pickle_round_trip_is_bit_identical():
    sim = Simulation(torque={"profile": "constant", "amplitude": 0.2}, **{"initial.angle_deg": 35})
    for _ in range(7):
        sim.step(0.01)
    copy = pickle.loads(pickle.dumps(sim))
    assert copy.snapshot() == sim.snapshot()
    assert copy.config == sim.config
    assert np.array_equal(state_of(copy), state_of(sim))
    for _ in range(5):
        sim.step(0.01)
        copy.step(0.01)
    assert np.array_equal(state_of(copy), state_of(sim))


TORQUE_TABLE = "time_s,torque_Nm\n0,0\n0.03,0.4\n0.2,-0.1\n"


def files_config(folder):
    """A coarse pendulum mesh (the CLI's `mesh` command: mesh/mesh.msh) and a torque table
    (torque.csv) in `folder`, and the configuration naming both by relative paths."""
    cli = os.environ.get("PENDULUM_FEM_CLI")
    assert cli, "PENDULUM_FEM_CLI is not set: run these tests through `cargo test --release --test suite python_package::`"
    subprocess.run(
        [cli, "mesh", "--set", "mesh.refine=0.5", "--out", str(folder / "mesh")], check=True, capture_output=True
    )
    (folder / "torque.csv").write_text(TORQUE_TABLE)
    return {"mesh.file": "mesh/mesh.msh", "torque.profile": "table", "torque.file": "torque.csv"}


def test_pickling_with_relative_mesh_and_torque_files_continues_bit_for_bit(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    cfg = files_config(tmp_path)
    never_pickled = Simulation(**cfg)
    sim = Simulation(**cfg)
    assert sim.config["mesh"]["file"] == "mesh/mesh.msh"
    for _ in range(5):
        never_pickled.step(0.01)
        sim.step(0.01)
    data = pickle.dumps(sim)
    # unpickled elsewhere: the pickle names the files by absolute paths, the fingerprint their contents
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    copy = pickle.loads(data)
    assert copy.config["torque"]["file"] == str(tmp_path / "torque.csv")
    assert copy.config["mesh"]["file"] == str(tmp_path / "mesh" / "mesh.msh")
    assert copy.snapshot() == sim.snapshot()
    for _ in range(5):
        never_pickled.step(0.01)
        copy.step(0.01)
    assert copy.tau != 0.0  # the table drives it
    assert np.array_equal(state_of(copy), state_of(never_pickled))
    assert copy.snapshot() == never_pickled.snapshot()


def test_unpickling_after_the_torque_table_was_edited_fails_naming_the_table(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    cfg = files_config(tmp_path)
    sim = Simulation(**cfg)
    sim.step(0.01)
    data = pickle.dumps(sim)
    (tmp_path / "torque.csv").write_text(TORQUE_TABLE.replace("0.4", "0.41"))
    with pytest.raises(ValueError, match=r"torque table \(times and torques of torque\.file = .*torque\.csv\) differs"):
        pickle.loads(data)
    # the file's content counts, not its name: the original table under another name restores
    (tmp_path / "renamed.csv").write_text(TORQUE_TABLE)
    same = Simulation(**{**cfg, "torque.file": "renamed.csv"})
    same.restore(sim.snapshot())


def test_an_unknown_key_raises_a_key_error_that_is_a_value_error_naming_the_key_and_the_allowed_keys(tmp_path):
    (tmp_path / "bad.toml").write_text("[material]\nyoungs_modulu = 1e7\n")
    for make in (
        lambda: Simulation(**{"material.youngs_modulu": 1e7}),
        lambda: Simulation(material={"youngs_modulu": 1e7}),
        lambda: Simulation({"material": {"youngs_modulu": 1e7}}),
        lambda: Simulation({"material.youngs_modulu": 1e7}),
        lambda: Simulation(tmp_path / "bad.toml"),
    ):
        with pytest.raises(KeyError) as raised:
            make()
        error = raised.value
        assert isinstance(error, ValueError) and isinstance(error, pendulum_fem.UnknownKeyError)
        assert error.key == "material.youngs_modulu"
        assert {"youngs_modulus", "poisson_ratio", "density"} <= set(error.allowed)
        text = str(error)
        assert text.startswith("unknown configuration key 'material.youngs_modulu' (allowed in [material]: "), text
        assert "youngs_modulus" in text
        assert "--set" not in text and "configuration:" not in text, text
    with pytest.raises(pendulum_fem.UnknownKeyError) as raised:
        Simulation(**{"materials.youngs_modulus": 1e7})
    assert raised.value.key == "materials.youngs_modulus"
    assert {"material", "mesh", "time"} <= set(raised.value.allowed)
    assert "allowed at the top level" in str(raised.value)
    # the exception pickles (to a worker and back) with its key and allowed keys
    copy = pickle.loads(pickle.dumps(raised.value))
    assert (type(copy), copy.key, copy.allowed, str(copy)) == (
        type(raised.value), raised.value.key, raised.value.allowed, str(raised.value))


def test_a_bad_value_raises_value_error_naming_the_key_without_the_command_lines_words():
    for make, key in (
        (lambda: Simulation(mesh={"max_size": -1.0}), r"mesh\.max_size"),
        (lambda: Simulation(dt=0.01), r"section\.name"),
        (lambda: Simulation(time={"dt": "abc"}), r"time\.dt"),
    ):
        with pytest.raises(ValueError, match=key) as raised:
            make()
        assert not isinstance(raised.value, KeyError), raised.value
        text = str(raised.value)
        assert "--set" not in text and not text.startswith("configuration:"), text


def test_a_missing_file_raises_file_not_found_error_naming_it(tmp_path):
    missing = tmp_path / "nope.toml"
    with pytest.raises(FileNotFoundError) as raised:
        Simulation(missing)
    assert raised.value.filename == str(missing)
    with pytest.raises(FileNotFoundError) as raised:
        Simulation(mesh={"file": str(tmp_path / "nope.msh")})
    assert raised.value.filename == str(tmp_path / "nope.msh")


def test_a_key_without_effect_warns_naming_it_and_the_key_that_makes_it_act():
    """The CLI's rule and words: a torque amplitude without a profile, and the ``[output]`` keys
    (a Simulation writes no files), each one ``UserWarning``; keys that act say nothing."""
    with pytest.warns(UserWarning) as caught:
        sim = Simulation(torque={"amplitude": 2}, output={"plots": False})
    said = [str(w.message) for w in caught if "has no effect" in str(w.message)]
    assert said == [
        'torque.amplitude = 2 has no effect: no torque profile is set (set torque.profile to one of '
        '"constant", "step", "ramp", "sine" or "table")',
        "output.plots = false has no effect: a simulation stepped by its caller writes no files (the [output] "
        "keys act in pendulum-fem run and its sweeps)",
    ], said
    assert sim.config["torque"]["amplitude"] == 2.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Simulation()
        Simulation(torque={"profile": "constant", "amplitude": 0.2}, **{"wall.x": -0.07})


def test_a_toml_file_a_dict_and_keywords_give_the_same_configuration(tmp_path):
    path = tmp_path / "p.toml"
    path.write_text('[material]\nyoungs_modulus = 1e9\nplane = "strain"\n[initial]\nangle_deg = 30\n')
    from_file = Simulation(path)
    from_str_path = Simulation(str(path))
    from_dict = Simulation({"material": {"youngs_modulus": 1e9, "plane": "strain"}, "initial.angle_deg": 30})
    from_keywords = Simulation(material={"youngs_modulus": 1e9, "plane": "strain"}, **{"initial.angle_deg": 30})
    assert from_file.config == from_str_path.config == from_dict.config == from_keywords.config
    assert from_file.config["material"]["youngs_modulus"] == 1e9
    # keywords win over the file; None leaves a key alone
    over = Simulation(path, **{"initial.angle_deg": 10, "time.dt": None})
    assert over.config["initial"]["angle_deg"] == 10 and over.config["time"]["dt"] == 0.01
    assert abs(over.theta - np.radians(10)) < 1e-6  # the soft body sags in its initial equilibrium


def test_step_releases_the_gil():
    sim = Simulation()
    started, done = threading.Event(), threading.Event()

    def work():
        started.set()
        sim.run(0.3, 0.01)  # 30 steps in one call
        done.set()

    worker = threading.Thread(target=work)
    worker.start()
    started.wait()
    counted = 0
    while not done.is_set():
        counted += 1
    worker.join()
    assert counted > 1000, f"the main thread ran only {counted} loops while the worker stepped"


def test_tau_declares_a_torque_input_before_the_first_step_and_is_refused_after():
    sim = Simulation()
    assert sim.tau == 0.0 and sim.config["torque"]["profile"] == "none"
    sim.tau = 0.25
    assert sim.tau == 0.25 and sim.config["torque"]["profile"] == "constant"
    sim.step(0.01)
    assert sim.run(0.02)["torque_Nm"][-1] == 0.25
    late = Simulation()
    late.step(0.01)
    with pytest.raises(ValueError, match="torque"):
        late.tau = 1.0
    declared = Simulation(torque={"profile": "constant"})
    declared.step(0.01)
    declared.tau = 1.0
    assert declared.tau == 1.0


def test_a_torque_beyond_the_hubs_limit_is_refused_and_the_held_torque_stays():
    # the default geometry at E = 1e6 Pa: 6.67e5 Pa of traction stress at the hinge edge's ends
    # per N·m, so a fifth of the modulus is 0.3 N·m
    sim = Simulation(material={"youngs_modulus": 1e6})
    sim.tau = 0.25
    sim.step(0.01)
    with pytest.raises(ValueError, match=r"torque input -0\.5 N·m .*at most 0\.3 N·m.*outside the model"):
        sim.tau = -0.5
    assert sim.tau == 0.25
    sim.step(0.01)


def test_alpha_follows_tau_at_once():
    sim = Simulation()
    sim.tau = 0.0
    for _ in range(3):
        sim.step(0.01)
    a0 = sim.alpha
    sim.tau = 1.0
    # a rigid body: Δα = Δτ / I (the deformation changes I by far less than 1e-3)
    assert sim.alpha - a0 == pytest.approx(1.0 / sim.inertia, rel=1e-3)


def test_fields_are_numpy_arrays_shaped_by_the_mesh():
    sim = Simulation()
    sim.step(0.01)
    n = sim.nodes.shape[0]
    assert sim.nodes.shape == (n, 2) and sim.nodes.dtype == np.float64
    assert sim.triangles.shape[1] == 6 and sim.triangles.dtype == np.int64
    assert sim.triangles.min() == 0 and sim.triangles.max() == n - 1
    assert sim.displacement.shape == sim.velocity.shape == (n, 2)
    assert sim.von_mises.shape == (n,) and sim.von_mises.max() > 0
    assert sim.cauchy_stress.shape == (n, 3)
    e = sim.energies
    assert set(e) == {"kinetic", "strain", "gravity", "contact", "total", "torque_work"}
    assert e["contact"] == 0.0
    assert e["total"] == pytest.approx(e["kinetic"] + e["strain"] + e["gravity"], rel=1e-15)
    # the body at 20° from the hanging position: head arc well clear of the plane x = wall.x
    x_head = sim.nodes[:, 0] + sim.displacement[:, 0]
    assert 0.0 < sim.gap <= x_head.max() - sim.config["wall"]["x"]
    assert sim.contact_force == 0.0 and sim.impacts == 0 and not sim.in_contact and sim.events == []
    assert 0.5 < sim.mass < 2.0 and sim.center_of_mass[1] < -0.1
    assert "Simulation" in repr(sim)


def test_invalid_steps_raise_value_error_and_change_nothing():
    sim = Simulation()
    before = sim.snapshot()
    for dt in (0.0, -0.01, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="dt"):
            sim.step(dt)
    assert sim.snapshot() == before
    with pytest.raises(ValueError, match="snapshot"):
        sim.restore(b"not a snapshot")
    other = Simulation(**{"material.youngs_modulus": 1e9})
    with pytest.raises(ValueError):
        sim.restore(other.snapshot())
    assert issubclass(ConvergenceError, RuntimeError)


def test_a_head_coming_round_the_deformable_blocks_face_raises_outside_model_error_and_changes_nothing():
    # thrown over the pivot, the head passes behind the block and comes round the end of its face
    # onto it (the face is the block's only contact surface): at t = 0.5 s through the CLI
    sim = Simulation(wall={"kind": "deformable"}, initial={"angular_velocity": 15.0})
    with pytest.raises(OutsideModelError, match="come round the face's end"):
        for _ in range(60):
            before = sim.snapshot()
            sim.step(0.01)
    assert sim.snapshot() == before
    assert 0.4 < sim.time < 0.6
    assert issubclass(OutsideModelError, RuntimeError) and not issubclass(OutsideModelError, ConvergenceError)


def test_importing_pendulum_fem_does_not_import_syssimx():
    code = "import sys, pendulum_fem; pendulum_fem.Simulation; assert 'syssimx' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True)


def test_ctrl_c_stops_a_run_at_a_step_boundary():
    code = """
import os, signal, threading, time, pendulum_fem
sim = pendulum_fem.Simulation()
threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
start = time.perf_counter()
try:
    sim.run(100.0, 0.01)
    raise SystemExit("run was not interrupted")
except KeyboardInterrupt:
    pass
assert time.perf_counter() - start < 5.0, "the interrupt took too long"
assert 0 < sim.steps < 10000 and abs(sim.time - sim.steps * 0.01) < 1e-9, (sim.steps, sim.time)
sim.step(0.01)  # the simulation goes on
print(sim.steps)
"""
    subprocess.run([sys.executable, "-c", code], check=True)


def test_run_with_the_wall_equals_the_cli_results_and_events_csv_bit_for_bit(cli_wall_results, cli_wall_events):
    header, rows = cli_wall_results
    sim = Simulation(**{"wall.kind": "rigid"})
    result = sim.run(1.0, 0.01)
    assert list(result) == header == pendulum_fem.csv_columns(wall=True)
    assert header[-4:] == ["gap_m", "contact_force_N", "contact_J", "impacts"]
    expected = np.array(rows)
    assert len(result["time_s"]) == len(rows) == 101
    for j, name in enumerate(header):
        got = result[name]
        assert got.dtype == np.float64 and got.shape == (101,)
        differ = np.flatnonzero(bits(got) != bits(expected[:, j]))
        assert differ.size == 0, f"{name}: first difference at row {differ[0]}: {got[differ[0]]!r} != {expected[differ[0], j]!r}"
    # the events, row for row and bit for bit
    event_header, event_rows = cli_wall_events
    assert event_header == pendulum_fem.event_columns()
    assert [list(e) for e in sim.events] == [event_header] * len(sim.events)
    assert len(sim.events) == len(event_rows) == 4  # two impacts: start and end of each
    for event, row in zip(sim.events, event_rows):
        for key, value in zip(event_header, row):
            if key == "event":
                assert event[key] == value
            else:
                assert bits([event[key]]) == bits([value]), f"{key}: {event[key]!r} != {value!r}"
    # the properties read the same state as the last row
    assert sim.gap == result["gap_m"][-1] and sim.contact_force == result["contact_force_N"][-1]
    assert sim.impacts == result["impacts"][-1] == 2
    assert sim.energies["contact"] == result["contact_J"][-1]


def test_the_wall_properties_follow_an_impact_and_round_trip_through_snapshots():
    sim = Simulation(**{"wall.kind": "rigid"})
    while sim.impacts == 0:
        before = sim.snapshot()
        sim.step(0.01)
    start = sim.events[0]
    assert start["event"] == "impact_start" and sim.time - 0.01 < start["time_s"] < sim.time
    # the impact (about 2 ms) ends in the next step: the head is off the wall again
    sim.step(0.01)
    assert [e["event"] for e in sim.events] == ["impact_start", "impact_end"] and sim.impacts == 1
    assert sim.events[1]["impulse_N_s"] > 0.0 and sim.events[1]["max_penetration_m"] > 0.0
    assert sim.gap > 0.0 and sim.contact_force == 0.0 and not sim.in_contact
    # stepped finely from the step's start: in contact, pressed, penetrating
    sim.restore(before)
    assert sim.impacts == 0 and sim.events == []
    while not sim.in_contact:
        sim.step(1e-4)
    assert sim.impacts == 1 and sim.gap < 0.0 and sim.contact_force > 0.0
    assert sim.energies["contact"] > 0.0
    copy = pickle.loads(pickle.dumps(sim))
    assert copy.events == sim.events and copy.impacts == 1 and copy.in_contact
    assert copy.gap == sim.gap and copy.contact_force == sim.contact_force


def test_off_the_wall_contact_force_is_a_positive_zero_in_the_property_and_the_columns():
    # the force sums clamped terms, −0.0 without penetration: reported as +0.0 (no `-0.0` shown)
    sim = Simulation(**{"wall.kind": "rigid", "initial.angle_deg": 20})
    assert sim.gap > 0.0
    assert sim.contact_force == 0.0 and math.copysign(1.0, sim.contact_force) == 1.0
    assert repr(sim.contact_force) == "0.0"
    rows = sim.run(0.1, 0.01)  # before the first impact (0.24 s)
    force = np.asarray(rows["contact_force_N"])
    assert np.all(force == 0.0) and not np.any(np.signbit(force)), force


def test_a_torque_input_declared_with_the_deformable_wall_keeps_the_mesh_of_both_bodies():
    # declaring tau rebuilds the model: the wall's block must not be appended a second time
    sim = pendulum_fem.Simulation(**{"wall.kind": "deformable", "time.end": 0.02})
    nodes, triangles = sim.nodes.copy(), sim.triangles.copy()
    sim.tau = 0.0
    assert np.array_equal(sim.nodes, nodes)
    assert np.array_equal(sim.triangles, triangles)
    sim.step(0.01)
    assert sim.gap > 0.0


def test_the_reduced_body_runs_from_python_conserving_energy_and_follows_the_full_model():
    """`model.kind = "reduced"` through the package: the energy is conserved to the solver's
    tolerance (1e-12 of the total), the angle follows the full model's within 1e-4 rad at
    dt = 0.01 s (the two time schemes' phase errors differ), and a snapshot of it replays bit for
    bit."""
    reduced = Simulation(model={"kind": "reduced"})
    rows = reduced.run(1.0, 0.01)
    full = Simulation().run(1.0, 0.01)
    total = rows["total_J"]
    assert np.max(np.abs(total - total[0])) < 1e-12 * abs(total[0])
    assert np.max(np.abs(rows["theta_rad"] - full["theta_rad"])) < 1e-4
    snap = reduced.snapshot()
    for _ in range(5):
        reduced.step(0.01)
    first = state_of(reduced)
    reduced.restore(snap)
    for _ in range(5):
        reduced.step(0.01)
    assert np.array_equal(state_of(reduced), first)
    # steel is where the reduced body applies: its error estimate stays far below the bound (1e-2)
    eta, _ = reduced.error_estimate
    assert eta < 1e-4
    assert Simulation().error_estimate is None


def test_the_reduced_body_strikes_the_deformable_wall_from_python_as_the_full_model_does():
    """The block reduced beside the pendulum (`wall.kind = "deformable"`) through the package: one
    impact in 0.4 s, as in the full model; the angle within 1e-4 rad of the full model's at
    dt = 0.01 s (the two time schemes' phase errors differ); the energy to 1e-12 of the total (the
    solver's tolerance); no warning (steel applies)."""
    wall = {"kind": "deformable"}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        reduced = Simulation(model={"kind": "reduced"}, wall=wall)
        rows = reduced.run(0.4, 0.01)
    assert not [w for w in caught if "does not apply" in str(w.message)]
    full_sim = Simulation(wall=wall)
    full = full_sim.run(0.4, 0.01)
    assert reduced.impacts == full_sim.impacts == 1
    total = rows["total_J"]
    assert np.max(np.abs(total - total[0])) < 1e-12 * abs(total[0])
    assert np.max(np.abs(rows["theta_rad"] - full["theta_rad"])) < 1e-4


def test_a_soft_reduced_pendulum_warns_once_that_it_does_not_apply():
    """A rubber pendulum (E = 0.1 MPa) is beyond the reduced body's linear modes: the package
    raises the run's one warning as a ``UserWarning`` naming the figure and the way out."""
    soft = {"youngs_modulus": 1e5, "poisson_ratio": 0.45, "density": 1000.0}
    with pytest.warns(UserWarning, match='does not apply here.*model.kind = "full"') as caught:
        sim = Simulation(model={"kind": "reduced"}, material=soft, initial={"angle_deg": 45.0})
        for _ in range(20):
            sim.step(0.01)
    assert len([w for w in caught if "does not apply" in str(w.message)]) == 1
    eta, _ = sim.error_estimate
    assert eta > 1.0
