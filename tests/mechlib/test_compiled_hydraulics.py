"""The `valve` servo-actuator in compiled kernels (issue 40 item 2, hydraulics): its states'
rates and advance (mechlib.elements.hydraulics.valve_states), the actuators packed with the
other force elements for the compiled Newton loop and dense rows
(mechlib.elements.compiled_forces), against the element's
Python evaluation and the Python path (`compiled="python"`). The physics is checked against
closed forms by tests/mechlib/test_servo_actuator.py and tests/verification/
test_servo_closed_valve.py, whose runs now take these kernels."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

import mechlib as ml
from mechlib.elements.compiled_forces import CompiledForces
from mechlib.elements.hydraulics import Controller, Cylinder, ServoActuator
from mechlib.elements.hydraulics.valve_states import advance_valve, valve_rates
from mechlib.elements.states import residual_size
from mechlib.system.system import System
from tests.mechlib.hydraulic_rig import REQUESTS, crossings, rig

SPRING_POINTS = (("rod", (0, 0, 0)), ("ground", (0.5, 0, 0)))
RAM = Cylinder(stroke=(-0.05, 0.1), leakage=0.0, stop_stiffness=0.0, stop_damping=0.0)


def _ram(spring: bool = True) -> ml.Mechanism:
    """The bench's hydraulic ram (benchmarks/kinds/hydraulic.py) in short: a 50 kg rod
    driven by a fully open valve against a spring of 1e5 N/m."""
    m = rig(lambda t: 0.3, mass=50.0, cylinder=RAM, controller=Controller(kp=1000.0, ki=0.0))
    if spring:
        m.add_force(ml.Spring("spring", SPRING_POINTS, 1e5, free_length=0.5))
    return m


def _actuator_system(mechanism: ml.Mechanism) -> tuple[System, ServoActuator]:
    """The bound system and its actuator `act`."""
    system = System(mechanism)
    act = mechanism.forces["act"]
    assert isinstance(act, ServoActuator)
    return system, act


def _constant(value: float, t: float) -> float:
    """A stroke demand (m) that holds `value` at every time t (s)."""
    return value


def test_compiled_rates_are_the_elements_python_rates() -> None:
    """valve_rates (the laws composed in one kernel) equal the element's `_evaluate`
    (the same laws called from Python) at states across the valve's range: within 1e-12
    of each rate's size (measured: equal to the last bit)."""
    _, act = _actuator_system(_ram())
    rng = np.random.default_rng(3)
    for _ in range(20):
        z = np.array(
            [
                rng.normal(0, 1e-3),
                rng.uniform(-1.2, 1.2),
                rng.normal(0, 300.0),
                rng.uniform(-1e6, 2.5e7),  # below the vapour floor too
                rng.uniform(-1e6, 2.5e7),
            ]
        )
        x, xd, demand = rng.uniform(-0.06, 0.11), rng.normal(0, 0.3), rng.uniform(-0.1, 0.1)
        act.command = functools.partial(_constant, demand)
        python = np.array(act._evaluate(0.0, x, xd, z)[0])
        out = np.empty(5)
        valve_rates(act._params, demand, x, xd, z, out)
        assert np.all(np.abs(out - python) <= 1e-12 * (np.abs(python) + 1e-300))


def test_advance_solves_the_trapezoidal_rule() -> None:
    """advance_valve leaves z = z0 + h/2 (f0 + f(z)) to the states' convergence rule
    (residual_size <= 1: 1e-12 of each state) from a start half a step away."""
    _, act = _actuator_system(_ram())
    z0 = np.array([0.0, 0.2, 500.0, 1.2e7, 0.9e7])
    f0 = np.empty(5)
    valve_rates(act._params, 0.3, 0.01, 0.05, z0, f0)
    h = 2e-4
    z = z0 + 0.5 * h * f0
    iterations = advance_valve(act._params, 0.3, 0.012, 0.06, z0, f0, h, z)
    f = np.empty(5)
    valve_rates(act._params, 0.3, 0.012, 0.06, z, f)
    assert 1 <= iterations < 20
    assert residual_size(z - z0 - 0.5 * h * (f0 + f), z) <= 1.0


def test_one_packer_takes_actuators_with_their_springs() -> None:
    """The ram (actuator and spring) is packed by the one packer of compiled element
    loads, the actuator with its states; a spring beside an actuator of another fidelity
    (whose states the kernels do not advance) is not; a switched-off actuator stays
    packed (its states still advance) but loads nothing."""
    system = System(_ram())
    packed = system.compiled_forces()
    assert packed is not None
    assert len(packed.actuators) == 1 and packed.args[0].shape[0] == 1  # one spring
    lag = rig(lambda t: 0.0, fidelity="lag")
    lag.add_force(ml.Spring("spring", SPRING_POINTS, 1e5, free_length=0.5))
    assert CompiledForces.of(System(lag)) is None
    off = _ram(spring=False)
    system = System(off)
    off.forces["act"].active = False
    packed = system.compiled_forces()
    assert packed is not None and len(packed.actuators) == 1
    packed.refresh(system, 0.0)
    assert packed.args[10][0, 3] == 0  # its `on` flag


@pytest.mark.parametrize("dense", [True, False])
def test_compiled_path_moves_the_ram_as_the_python_path(dense: bool) -> None:
    """The ram for 0.03 s at tolerance 1e-6 in the compiled Newton loop and row blocks
    against `compiled="python"`: the same steps, iterations and rejections; the stroke
    within 1e-9 of its range and the chamber pressures (the rows' interpolated states)
    within 1e-9 of the supply pressure (measured: 1e-12 and 3e-12)."""
    runs = {}
    for compiled in ("steps", "python"):
        sol = ml.solve(
            _ram(),
            ml.Dynamic(end=0.03, step=1e-4, tolerance=1e-6, compiled=compiled, dense=dense),
            requests=REQUESTS,
        )
        assert sol.ok, sol.message
        runs[compiled] = sol
    fast, slow = runs["steps"], runs["python"]
    assert (fast.stats.steps, fast.stats.rejected_steps) == (
        slow.stats.steps,
        slow.stats.rejected_steps,
    )
    assert fast.stats.newton_iterations == slow.stats.newton_iterations
    x_fast, x_slow = fast.channels["x.value"], slow.channels["x.value"]
    assert np.ptp(x_slow) > 3e-3  # the ram moves (3.8 mm)
    assert np.max(np.abs(x_fast - x_slow)) <= 1e-9 * np.ptp(x_slow)
    for p in ("act.p1", "act.p2"):
        assert np.max(np.abs(fast.channels[p] - slow.channels[p])) <= 1e-9 * 206.8e5


def test_closed_valve_rings_at_the_hydraulic_frequency_in_the_compiled_path() -> None:
    """Valve closed, no friction nor leakage: the compiled path's rod rings at f_h =
    sqrt(beta (A1^2/V1 + A2^2/V2) / M) / 2 pi (Merritt 1967) within 5e-4 (as the Python
    path in test_servo_actuator.py; measured -5e-5)."""
    cylinder = Cylinder(viscous_friction=0.0, leakage=0.0)
    sol = ml.solve(
        rig(controller=Controller(kp=0.0, ki=0.0), cylinder=cylinder),
        ml.Dynamic(end=0.03, step=1e-4, tolerance=1e-6, compiled="steps"),
        requests=REQUESTS,
        initial=[ml.InitialValue("slide", value=0.0, rate=0.01)],
    )
    up = crossings(sol.time, sol.channels["x.value"])
    frequency = (len(up) - 1) / (up[-1] - up[0])
    expected = math.sqrt(cylinder.hydraulic_stiffness(0.0) / 100.0) / (2 * math.pi)
    assert abs(frequency / expected - 1.0) < 5e-4
