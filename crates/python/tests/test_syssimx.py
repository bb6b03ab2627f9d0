"""The syssimx adapter: a closed loop with a PD controller, exact rollback, CLI steps inside macro steps."""

import math

import pytest

from syssimx import Connection, CoSimComponent, PortSpec, PortType, System
from syssimx.system.algorithms import HybridAlgorithm

from pendulum_fem import Simulation
from pendulum_fem._core import internal_steps as core_internal_steps
from pendulum_fem.syssimx import PendulumFem, impact_parity, internal_steps

THETA_REF = 0.3  # rad
KP = 20.0  # N m / rad
KD = 2.0  # N m s / rad


def magnitude(value, unit):
    return float(value.to(unit).magnitude) if hasattr(value, "to") else float(value)


class PD(CoSimComponent):
    """τ = K_p (θ_ref − θ) − K_d ω, computed from the inputs of the step's end."""

    def __init__(self, name, kp, kd, theta_ref):
        super().__init__(name)
        self.input_specs = {
            "theta": PortSpec("theta", PortType.REAL, "in", unit="rad"),
            "omega": PortSpec("omega", PortType.REAL, "in", unit="rad/s"),
        }
        self.output_specs = {"tau": PortSpec("tau", PortType.REAL, "out", unit="N.m")}
        self.direct_feedthrough = {"tau": {"theta", "omega"}}
        self.gains = (kp, kd, theta_ref)

    def _initialize_component(self, t0):
        pass

    def _do_step_internal(self, t, dt):
        pass

    def _update_output_states(self, t=None, event_names=None):
        kp, kd, ref = self.gains
        theta = magnitude(self.inputs["theta"].get(), "rad")
        omega = magnitude(self.inputs["omega"].get(), "rad/s")
        self.outputs["tau"].set(kp * (ref - theta) - kd * omega, t=t)

    def evaluate_outputs(self, inputs, t=None):
        if inputs:
            self.set_inputs(inputs, t=t)
        self._update_output_states(t)
        return {name: port.get() for name, port in self.outputs.items()}


def static_balance(kp, theta_ref, mgd):
    """The θ with K_p (θ_ref − θ) = m g d sin θ (bisection on [0, θ_ref])."""
    lo, hi = 0.0, theta_ref
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if kp * (theta_ref - mid) > mgd * math.sin(mid):
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def closed_loop(t_end):
    plant = PendulumFem("pendulum", **{"initial.angle_deg": 0})
    controller = PD("controller", KP, KD, THETA_REF)
    system = System("pd_loop")
    system.add_component(plant)
    system.add_component(controller)
    system.add_connection(Connection("pendulum", "theta", "controller", "theta"))
    system.add_connection(Connection("pendulum", "omega", "controller", "omega"))
    system.add_connection(Connection("controller", "tau", "pendulum", "tau"))
    system.initialize(0.0)
    system.run(0.0, t_end, 0.01)
    return system, plant


def test_pd_loop_settles_at_the_static_balance():
    system, plant = closed_loop(2.0)
    sim = plant.sim
    m, g = sim.mass, sim.config["gravity"]["g"]
    d = math.hypot(*sim.center_of_mass)
    expected = static_balance(KP, THETA_REF, m * g * d)
    theta = magnitude(plant.outputs["theta"].get(), "rad")
    assert abs(theta - expected) < 1e-4, f"settled at {theta:.7f} rad, balance at {expected:.7f} rad"
    assert abs(magnitude(plant.outputs["omega"].get(), "rad/s")) < 1e-3
    # the controller's torque is the plant's held input
    assert sim.tau == pytest.approx(KP * (THETA_REF - theta), abs=1e-3)
    times, values = plant.get_history_arrays()
    assert times[-1] == pytest.approx(2.0) and len(values["theta"]) == len(times)


def test_a_checkpoint_rolls_back_bit_for_bit():
    plant = PendulumFem("pendulum", **{"initial.angle_deg": 10})
    assert plant.supports_rollback
    plant.initialize(0.0)
    plant.set_inputs({"tau": 0.3}, t=0.0)
    plant.do_step(0.0, 0.05)
    checkpoint = plant.checkpoint()
    plant.set_inputs({"tau": -0.2}, t=0.05)
    plant.do_step(0.05, 0.03)
    first = (plant.sim.snapshot(), plant.get_outputs())
    plant.restore_checkpoint(checkpoint)
    assert plant.t == 0.05 and plant.sim.tau == 0.3
    plant.set_inputs({"tau": -0.2}, t=0.05)
    plant.do_step(0.05, 0.03)
    assert plant.sim.snapshot() == first[0]
    assert plant.get_outputs() == first[1]


def test_macro_steps_take_the_cli_steps_inside():
    assert internal_steps(0.05, 0.01) == (5, 0.01)
    assert internal_steps(0.01, 0.01) == (1, 0.01)
    assert internal_steps(0.004, 0.01) == (1, 0.004)
    n, h = internal_steps(0.025, 0.01)
    assert n == 3 and h == pytest.approx(0.025 / 3)
    plant = PendulumFem("pendulum", torque={"profile": "constant"})
    plant.initialize(0.0)
    reference = Simulation(torque={"profile": "constant"}).run(0.2, 0.01)
    for k in range(4):
        plant.do_step(0.05 * k, 0.05)
        row = 5 * (k + 1)
        assert plant.sim.theta == reference["theta_rad"][row]
        assert plant.sim.time == reference["time_s"][row]


def test_fmpy_style_macro_steps_take_the_internal_steps_of_the_core_rule():
    # fmpy's step sizes: differences of communication points, (k + 1)·0.01 − k·0.01, rounded
    assert internal_steps is core_internal_steps  # the adapter has no rule of its own
    macro = [(k * 0.01, (k + 1) * 0.01 - k * 0.01) for k in range(12)]
    assert len({h for _, h in macro}) > 1, "the differences carry rounding"
    for max_step in (0.01, 0.004):
        plant = PendulumFem("pendulum", torque={"profile": "constant"}, max_internal_step=max_step)
        plant.initialize(0.0)
        reference = Simulation(torque={"profile": "constant"})
        reference.tau = 0.0
        last, taken = None, []
        for t, h in macro:
            plant.do_step(t, h)
            n, step = core_internal_steps(h, max_step, last)
            for _ in range(n):
                reference.step(step)
            taken.append((n, step))
            last = step
        # the core rule snaps to max_step or reuses the first internal step: one step size only
        assert len(set(taken)) == 1, taken
        assert taken[0] == ((1, 0.01) if max_step == 0.01 else (3, 0.01 / 3))
        assert plant.sim.steps == reference.steps == 12 * taken[0][0]
        assert plant.sim.snapshot() == reference.snapshot(), f"max_internal_step = {max_step}"


def test_an_absurd_max_internal_step_raises_instead_of_looping():
    with pytest.raises(ValueError, match="allowed at most 1000000"):
        core_internal_steps(0.01, 1e-12)
    with pytest.raises(ValueError, match="longest internal step"):
        core_internal_steps(0.01, float("nan"))
    plant = PendulumFem("pendulum", max_internal_step=1e-12)
    plant.initialize(0.0)
    before = plant.sim.snapshot()
    with pytest.raises(ValueError, match=r"\[pendulum\] macro step dt = 0.01 s: .*allowed at most 1000000"):
        plant.do_step(0.0, 0.01)
    assert plant.sim.snapshot() == before and plant.sim.steps == 0


def test_alpha_answers_tau_within_the_instant():
    plant = PendulumFem("pendulum")
    plant.initialize(0.0)
    alpha0 = magnitude(plant.outputs["alpha"].get(), "rad/s^2")
    out = plant.evaluate_outputs({"tau": 1.0})
    assert magnitude(out["alpha"], "rad/s^2") - alpha0 == pytest.approx(1.0 / plant.sim.inertia, rel=1e-3)
    assert plant.direct_feedthrough["alpha"] == {"tau"} and plant.direct_feedthrough["theta"] == set()


def crossing_time(h_coarse, h_fine):
    """When θ first falls through 0 on the trajectory of steps h_coarse: the last coarse step before
    it, then steps of h_fine from its snapshot, then linear interpolation."""
    sim = Simulation(torque={"profile": "constant"})
    while True:
        snap = sim.snapshot()
        sim.step(h_coarse)
        if sim.theta < 0:
            break
    sim.restore(snap)
    while sim.theta > 0:
        t0, th0 = sim.time, sim.theta
        sim.step(h_fine)
    return t0 + (sim.time - t0) * th0 / (th0 - sim.theta)


def test_the_hybrid_algorithm_locates_a_crossing_by_rollback():
    # θ falls through 0 once in 0.3 s (the swing from 20°, a quarter period); syssimx's hybrid
    # algorithm brackets it by stepping the component from checkpoints again and again
    plant = PendulumFem("pendulum", max_internal_step=1e-3)
    plant.add_event_indicator("upright", lambda c: c.sim.theta, direction=-1)
    system = System("crossing")
    system.add_component(plant)
    system.set_algorithm(HybridAlgorithm())
    system.initialize(0.0)
    system.run(0.0, 0.3, 0.01)
    events = system.history.get_all_event_histories()[("pendulum", "upright")]
    assert len(events) == 1
    expected = crossing_time(1e-3, 1e-6)
    # syssimx stops when |indicator| < tol_value = 1e-6 rad, i.e. within 1e-6 / ω ≈ 7e-7 s
    assert abs(events[0].t - expected) < 1e-6, f"located at {events[0].t!r} s, the trajectory crosses at {expected!r} s"
    assert plant.sim.theta < 0 and abs(plant.sim.time - 0.3) < 1e-6


def test_the_hybrid_algorithm_locates_the_wall_impacts_through_contact_count():
    # the stepper's own events, stepped as the CLI steps (0.01 s): impact starts at ~0.2395 s and
    # ~0.7208 s; the impact (~2 ms) starts and ends inside one macro step, so `gap` is positive at
    # every communication point around it and only the count shows it
    reference = Simulation(**{"wall.kind": "rigid"})
    reference.run(0.8, 0.01)
    starts = [e["time_s"] for e in reference.events if e["event"] == "impact_start"]
    assert len(starts) == 2
    plant = PendulumFem("pendulum", **{"wall.kind": "rigid"})
    assert plant.output_specs["contact_count"].type == PortType.INT
    plant.add_event_indicator("wall_hit", impact_parity)
    system = System("wall")
    system.add_component(plant)
    system.set_algorithm(HybridAlgorithm())
    system.initialize(0.0)
    # the event port exists: no output of the component is named like the event
    assert plant.output_specs["wall_hit"].type == PortType.EVENT
    system.run(0.0, 0.8, 0.01)
    located = [e.t for e in system.history.get_all_event_histories()[("pendulum", "wall_hit")]]
    errors = [abs(a - b) for a, b in zip(located, starts)]
    print(f"impact starts: stepper {starts}, located {located}, differences {errors} s")
    assert len(located) == 2 and max(errors) < 1e-4, (located, starts)
    assert plant.outputs["contact_count"].get() == 2 == plant.sim.impacts
    assert abs(plant.sim.time - 0.8) < 1e-6
