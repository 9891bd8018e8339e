"""Element states in dense rows (mechlib.solvers.dense_states): the cubic Hermite interpolant
of their values and rates at a step's two ends, in the Python rows, the compiled blocks and
the compiled whole runs alike (issue 35: the closed-valve servo's pressure crests missed
between steps by the straight line of before).

References:
- the interpolant itself: exact for a cubic; on sin(t) its error falls 16 times when the
  step halves (order 4), the straight line's 4 times (order 2);
- the closed-valve servo-actuator (no flow through the valve, no leakage): the chamber
  continuity p1' = -beta A1 x' / V1(x) integrates to the closed form
  p1 = p1(0) - beta ln(V1(x) / V1(x(0))) (Merritt, Hydraulic Control Systems, 1967, with a
  constant bulk modulus), p2 alike: every row's pressure against its own stroke, between
  the steps as at them.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import mechlib as ml
from mechlib.elements.hydraulics import Controller, Cylinder, HeldDemand
from mechlib.solvers.dense_states import hermite_states, states_between
from tests.mechlib.hydraulic_rig import REQUESTS, rig

CYLINDER = Cylinder(viscous_friction=0.0, leakage=0.0)


def _sine_error(h: float, hermite: bool) -> float:
    """The largest error of the rows (every 1/64 of the step) of sin(t) over [0, 2 pi]
    in steps of h (s) from the values (and rates) at the step ends."""
    worst = 0.0
    for t0 in np.arange(0.0, 2.0 * np.pi, h):
        z0, f0 = np.array([np.sin(t0)]), np.array([np.cos(t0)])
        z1, f1 = np.array([np.sin(t0 + h)]), np.array([np.cos(t0 + h)])
        for w in np.linspace(0.0, 1.0, 65):
            if hermite:
                value = hermite_states(z0, f0, z1, f1, h, w, np.empty(1))[0]
            else:
                value = states_between((z0, None), (z1, None), h, w)[0]
            worst = max(worst, abs(value - np.sin(t0 + w * h)))
    return worst


def test_hermite_states_are_exact_for_a_cubic_and_fourth_order() -> None:
    """A cubic z = 1 - 2t + 3t^2 - t^3 (two states: it and 5 z) to round-off; on sin(t) the
    error ratio over h = 0.4 and 0.2 is 16 within 10 % (h^4 / 384: measured 15.7, largest
    error 6.6e-5 at h = 0.4) where the straight line's is 4 (h^2 / 8: 3.9)."""
    t0, h = 0.3, 0.7

    def cubic(t):
        return 1.0 - 2.0 * t + 3.0 * t**2 - t**3

    def slope(t):
        return -2.0 + 6.0 * t - 3.0 * t**2

    z0, z1 = np.array([cubic(t0), 5 * cubic(t0)]), np.array([cubic(t0 + h), 5 * cubic(t0 + h)])
    f0, f1 = np.array([slope(t0), 5 * slope(t0)]), np.array([slope(t0 + h), 5 * slope(t0 + h)])
    for w in (0.0, 0.25, 0.5, 0.9, 1.0):
        got = states_between((z0, f0), (z1, f1), h, w)
        assert np.allclose(got, [cubic(t0 + w * h), 5 * cubic(t0 + w * h)], rtol=0, atol=1e-14)
    coarse, fine = _sine_error(0.4, True), _sine_error(0.2, True)
    assert coarse <= 0.4**4 / 384 * 1.05
    assert abs(coarse / fine / 16.0 - 1.0) < 0.1
    assert abs(_sine_error(0.4, False) / _sine_error(0.2, False) / 4.0 - 1.0) < 0.1


def test_states_without_rates_at_both_ends_are_linear() -> None:
    """A stepper that does not advance the states (the same rates at both ends, or none)
    gets them linearly: constant states stay constant."""
    z, f = np.array([2.0]), np.array([3.0])
    assert states_between((z, f), (z, f), 0.1, 0.3)[0] == 2.0
    assert states_between((z, None), (z + 1.0, None), 0.1, 0.25)[0] == 2.25


def _closed_valve(compiled: str, events=()) -> ml.Solution:
    """The rig's closed valve (held demand 0, no gain, no friction nor leakage), the rod
    started at 0.01 m/s: 0.03 s of its 76 Hz ringing at tolerance 1e-4, rows every 20 us
    (about 34 rows a step)."""
    mechanism = rig(HeldDemand(0.0), controller=Controller(kp=0.0, ki=0.0), cylinder=CYLINDER)
    analysis = ml.Dynamic(end=0.03, step=2e-5, tolerance=1e-4, dense=True)
    sol = ml.solve(
        mechanism,
        dataclasses.replace(analysis, compiled=compiled),
        initial=[ml.InitialValue("slide", value=0.0, rate=0.01)],
        requests=REQUESTS,
        events=events,
    )
    assert sol.ok, sol.message
    return sol


def _pressure_misses(sol: ml.Solution) -> tuple[float, float]:
    """(the largest |p - p(x)| of both chambers over the rows (Pa), p1's amplitude (Pa))
    against the closed form at each row's own stroke."""
    x, p1, p2 = (sol.channels[k] for k in ("x.value", "act.p1", "act.p2"))
    lo, hi = CYLINDER.stroke
    v1 = CYLINDER.dead_volume_1 + CYLINDER.area_1 * (x - lo)
    v2 = CYLINDER.dead_volume_2 + CYLINDER.area_2 * (hi - x)
    beta = CYLINDER.bulk_modulus
    e1 = p1 - (p1[0] - beta * np.log(v1 / v1[0]))
    e2 = p2 - (p2[0] - beta * np.log(v2 / v2[0]))
    return float(max(np.abs(e1).max(), np.abs(e2).max())), float(np.ptp(p1) / 2)


@pytest.mark.parametrize("compiled", ["runs", "steps", "python"])
def test_closed_valve_pressures_between_steps_follow_the_closed_form(compiled: str) -> None:
    """Every row's chamber pressures within 1e-3 of p1's amplitude (2.4e5 Pa) of the closed
    form at the row's stroke: in compiled whole runs (run_states), in Python steps with
    compiled blocks of rows (dense_compiled.project_loaded_rows) and in Python rows.
    Measured 44 steps (omega h about 0.33): 2.9e-4 of the amplitude (70 Pa, the same on
    all three paths) with cubic Hermite rows; 3.2e-2 (7566 Pa) with the states linear
    between steps, as before."""
    miss, amplitude = _pressure_misses(_closed_valve(compiled))
    assert amplitude > 2e5
    assert miss <= 1e-3 * amplitude, (miss, amplitude)


def test_rows_before_an_event_follow_the_closed_form() -> None:
    """An event with no action where the stroke first passes 10 um (armed: Python steps;
    the rows before it within its step end at the event's accepted states and rates, the
    run restarts there): the rows' pressures as above, within 1e-3 of the amplitude
    (measured 3.9e-4, 94 Pa; 4.0e-2, 9520 Pa, with the states linear between steps)."""
    mark = ml.Event("mark", lambda t, view: view.travel("slide") - 1e-5, ())
    sol = _closed_valve("runs", [mark])
    assert len(sol.events) == 1 and 0.0 < sol.events[0].time < 0.03
    miss, amplitude = _pressure_misses(sol)
    assert miss <= 1e-3 * amplitude, (miss, amplitude)


def test_radau_refuses_element_states() -> None:
    """Radau's right-hand side holds positions and velocities only: with a servo-actuator
    its chamber pressures stayed at their initial values (the oil column no spring, the
    rod coasting at its initial 0.01 m/s, reported ok); now a model error naming the
    element. Generalized-alpha solves the same model."""
    mechanism = rig(HeldDemand(0.0), controller=Controller(kp=0.0, ki=0.0), cylinder=CYLINDER)
    start = [ml.InitialValue("slide", value=0.0, rate=0.01)]
    with pytest.raises(ml.ModelError, match=r"'act'.*drop 'integrator: radau'"):
        ml.solve(mechanism, ml.Dynamic(end=0.002, step=1e-3, integrator="radau"), initial=start)
    sol = ml.solve(mechanism, ml.Dynamic(end=0.002, step=1e-3), initial=start)
    assert sol.ok and sol.stats.steps > 0
