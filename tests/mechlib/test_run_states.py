"""Element states in the compiled whole runs (mechlib.solvers.genalpha.run_states): the
`valve` servo-actuator with a held stroke demand (HeldDemand) runs its steps in one compiled
call, its five states advanced in the run kernel.

- Against the loop it replaces (`compiled="steps"`: every step from Python, the compiled
  Newton loop): the bench's ram (benchmarks/kinds/hydraulic.py) takes the same accepted and
  rejected steps, and its stroke and chamber pressures (the rows' interpolated states
  included) agree to round-off, with dense rows and with steps landing on the output times.
- Against closed forms, through the runs (Merritt, Hydraulic Control Systems, 1967): the
  closed valve rings at f_h = sqrt(beta (A1^2/V1 + A2^2/V2) / M) / 2 pi, the fully open
  valve drives the rod at v = (Q_R / A) sqrt((p_s - p_r) / dp_R).
- A demand that is a function of time keeps the steps in Python.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import mechlib as ml
from mechlib.elements.hydraulics import Controller, Cylinder, HeldDemand, ServoActuator
from mechlib.elements.hydraulics.command import held_value
from tests.mechlib.hydraulic_rig import REQUESTS, crossings, rig
from tests.mechlib.test_compiled_forces import _kernel_steps

SPRING_POINTS = (("rod", (0, 0, 0)), ("ground", (0.5, 0, 0)))
RAM = Cylinder(stroke=(-0.05, 0.1), leakage=0.0, stop_stiffness=0.0, stop_damping=0.0)
FRICTIONLESS = Cylinder(viscous_friction=0.0, leakage=0.0)
TOL_SAME = 1e-9  # of the stroke's range, of the supply pressure
SUPPLY = 206.8e5  # Pa


def _ram(command=None) -> ml.Mechanism:
    """The bench's hydraulic ram in short: a 50 kg rod driven by a fully open valve (the
    controller saturated by a held 0.3 m demand unless `command` is given) against a
    spring of 1e5 N/m."""
    demand = HeldDemand(0.3) if command is None else command
    m = rig(demand, mass=50.0, cylinder=RAM, controller=Controller(kp=1000.0, ki=0.0))
    m.add_force(ml.Spring("spring", SPRING_POINTS, 1e5, free_length=0.5))
    return m


def _solve(mechanism, analysis, monkeypatch, initial=()) -> tuple[ml.Solution, int]:
    """The solution and the accepted steps the compiled runs took."""
    return _kernel_steps(mechanism, analysis, initial, REQUESTS, monkeypatch)


def test_a_held_demand_is_read_once_and_a_function_of_time_is_not() -> None:
    """HeldDemand gives its value at every time and says so; a plain function does not."""
    held = HeldDemand(0.3)
    assert held(0.0) == held(7.5) == 0.3
    assert held_value(held) == 0.3
    assert held_value(lambda t: 0.3) is None


@pytest.mark.parametrize("dense", [True, False])
def test_runs_move_the_ram_as_the_python_steps(dense: bool, monkeypatch) -> None:
    """The ram for 0.05 s at tolerance 1e-5 (the bench's) in compiled runs and with every
    step from Python: the same accepted and rejected steps; the stroke within 1e-9 of its
    range and the chamber pressures within 1e-9 of the supply pressure (measured: dense
    1.6e-11 and 2.2e-10, steps 3.3e-11 and 1.1e-10; the spool opening 4.4e-13 and 0); the
    kernel took all but the first few steps."""
    analysis = ml.Dynamic(end=0.05, step=1e-4, tolerance=1e-5, dense=dense)
    fast, kernel = _solve(_ram(), dataclasses.replace(analysis, compiled="runs"), monkeypatch)
    slow, none = _solve(_ram(), dataclasses.replace(analysis, compiled="steps"), monkeypatch)
    assert none == 0
    assert (fast.stats.steps, fast.stats.rejected_steps) == (
        slow.stats.steps,
        slow.stats.rejected_steps,
    )
    assert kernel >= fast.stats.steps - 3
    x_fast, x_slow = fast.channels["x.value"], slow.channels["x.value"]
    assert np.ptp(x_slow) > 5e-3  # the ram moves
    assert np.max(np.abs(x_fast - x_slow)) <= TOL_SAME * np.ptp(x_slow)
    for p in ("act.p1", "act.p2", "act.spool"):
        scale = 1.0 if p == "act.spool" else SUPPLY
        assert np.max(np.abs(fast.channels[p] - slow.channels[p])) <= TOL_SAME * scale


def test_closed_valve_rings_at_the_hydraulic_frequency_in_runs(monkeypatch) -> None:
    """Valve closed (held demand 0, no gain), no friction nor leakage, the rod started at
    0.01 m/s: it rings at f_h within 5e-4 (as the Python path in test_servo_actuator.py;
    measured -1.9e-4, as the Python steps), every step but the first few in the kernel."""
    mechanism = rig(HeldDemand(0.0), controller=Controller(kp=0.0, ki=0.0), cylinder=FRICTIONLESS)
    sol, kernel = _solve(
        mechanism,
        ml.Dynamic(end=0.03, step=1e-4, tolerance=1e-6),
        monkeypatch,
        initial=[ml.InitialValue("slide", value=0.0, rate=0.01)],
    )
    assert kernel >= sol.stats.steps - 3
    up = crossings(sol.time, sol.channels["x.value"])
    frequency = (len(up) - 1) / (up[-1] - up[0])
    expected = math.sqrt(FRICTIONLESS.hydraulic_stiffness(0.0) / 100.0) / (2 * math.pi)
    assert abs(frequency / expected - 1.0) < 5e-4


def test_full_open_speed_follows_the_rated_flow_in_runs(monkeypatch) -> None:
    """A held 45 mm demand saturates the current (spool fully open): the mean speed over
    0.05-0.15 s within 2e-3 of (Q_R/A) sqrt((p_s - p_r)/dp_R) (as in test_servo_actuator.py;
    measured -3.8e-4), every step but the first few in the kernel."""
    sol, kernel = _solve(
        rig(HeldDemand(0.045), cylinder=FRICTIONLESS),
        ml.Dynamic(end=0.15, step=2e-3),
        monkeypatch,
    )
    assert kernel >= sol.stats.steps - 3
    t, x = sol.time, sol.channels["x.value"]
    window = t >= 0.05
    speed = np.polyfit(t[window], x[window], 1)[0]
    a = ServoActuator("a", (("g", (0, 0, 0)), ("g", (1, 0, 0))), HeldDemand(0.0))
    valve, supply = a.valve, a.supply
    drop = supply.pressure - supply.return_pressure
    expected = valve.rated_flow / FRICTIONLESS.area_1 * math.sqrt(drop / valve.rated_pressure_drop)
    assert abs(speed / expected - 1.0) < 2e-3


def test_a_demand_in_time_keeps_the_steps_in_python(monkeypatch) -> None:
    """A ramp demand (a function of time, which only Python evaluates): no run."""
    sol, kernel = _solve(
        _ram(lambda t: 0.1 * t), ml.Dynamic(end=0.01, step=1e-4, tolerance=1e-5), monkeypatch
    )
    assert kernel == 0 and sol.stats.steps > 0
