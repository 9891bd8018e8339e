"""Element states: first-order ODEs integrated with the mechanism (issue 3 item 10).

Reference: a force that builds up as a first-order lag, tau dz/dt + z = F0, pushing a slider
of mass m from rest: z = F0 (1 - exp(-t/tau)), x = F0/m (t^2/2 - tau t + tau^2 (1 -
exp(-t/tau))) (integrate twice).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

import mechlib as ml


@dataclass
class Lag:
    """Force (N, along x on `body`) with tau dz/dt + z = F0: one internal state."""

    name: str
    body: str
    tau: float
    F0: float
    effect: str = "loads"
    active: bool = True
    n_states: int = 1
    output_units: ClassVar[dict[str, str]] = {"value": "N"}

    def bind(self, system) -> None:
        self._b = system.body_index(self.body)

    def initial_states(self) -> list[float]:
        return [0.0]

    def state_rates(self, view, z) -> list[float]:
        return [(self.F0 - z[0]) / self.tau]

    def apply(self, view, F, N) -> None:
        F[self._b, 0] += view.states(self)[0]

    def output(self, view) -> dict[str, float]:
        return {"value": float(view.states(self)[0])}


def _slider(tau: float) -> ml.Mechanism:
    mech = ml.Mechanism()
    mech.add_body("s", mass=2.0, cm=(0, 0, 0), inertia=[1, 1, 1])
    mech.add_joint("g", "prismatic", bodies=("s", "ground"), at=(0, 0, 0), axis=(1, 0, 0))
    mech.add_force(Lag("lag", "s", tau, 4.0))
    return mech


def test_lag_state_and_motion_match_the_closed_form() -> None:
    """State within 1e-5 of F0 and travel within 1e-5 of its peak (tolerance 1e-8): the
    trapezoidal rule on the state is second order like the mechanism."""
    tau, F0, m = 0.1, 4.0, 2.0
    sol = ml.solve(
        _slider(tau),
        ml.Dynamic(end=0.5, step=0.01, tolerance=1e-8),
        requests=[ml.ElementOutput("z", "lag"), ml.JointCoordinate("x", "g", "travel")],
    )
    t = sol.time
    z = F0 * (1 - np.exp(-t / tau))
    x = F0 / m * (t * t / 2 - tau * t + tau * tau * (1 - np.exp(-t / tau)))
    assert np.abs(sol.channels["z.value"] - z).max() < 1e-5 * F0
    assert np.abs(sol.channels["x.value"] - x).max() < 1e-5 * x.max()


def test_stiff_state_stays_bounded() -> None:
    """tau = 1e-4 s with outputs every 10 ms: no failure, the state never exceeds F0 by
    more than 1 % (A-stable trapezoidal rule) and ends at F0."""
    sol = ml.solve(
        _slider(1e-4), ml.Dynamic(end=0.5, step=0.01), requests=[ml.ElementOutput("z", "lag")]
    )
    z = sol.channels["z.value"]
    assert sol.ok
    assert z.max() <= 4.0 * 1.01
    assert abs(z[-1] - 4.0) < 1e-3


@dataclass
class Follower:
    """Force c z (N, along x on `body`) with tau dz/dt + z = x, x the travel of `joint`
    (m): a first-order lag of a prescribed position, one internal state."""

    name: str
    body: str
    joint: str
    tau: float
    c: float
    effect: str = "loads"
    active: bool = True
    n_states: int = 1
    output_units: ClassVar[dict[str, str]] = {"value": "m"}

    def bind(self, system) -> None:
        self._b = system.body_index(self.body)

    def initial_states(self) -> list[float]:
        return [0.0]

    def state_rates(self, view, z) -> list[float]:
        return [(view.travel(self.joint) - z[0]) / self.tau]

    def apply(self, view, F, N) -> None:
        F[self._b, 0] += self.c * view.states(self)[0]

    def output(self, view) -> dict[str, float]:
        return {"value": float(view.states(self)[0])}


def _driven_slider(tau: float, speed: float, c: float) -> ml.Mechanism:
    from tests.mechlib._models import Ramp

    mech = ml.Mechanism(gravity=(0.0, 0.0, 0.0))
    mech.add_body("s", mass=2.0, cm=(0, 0, 0), inertia=[1, 1, 1])
    mech.add_joint("g", "prismatic", bodies=("s", "ground"), at=(0, 0, 0), axis=(1, 0, 0))
    mech.add_motion("drive", joint="g", function=Ramp(0.0, speed))
    mech.add_force(Follower("lag", "s", "g", tau, c))
    return mech


def _lag_error(analysis) -> tuple[float, float]:
    """Largest errors of z and of the drive's effort |f| = c z against the closed form."""
    tau, a, c = 0.1, 2.0, 50.0
    sol = ml.solve(
        _driven_slider(tau, a, c),
        analysis,
        requests=[ml.ElementOutput("z", "lag"), ml.MotionEffort("f", "drive")],
    )
    assert sol.ok
    t = sol.time
    z = a * (t - tau * (1.0 - np.exp(-t / tau)))
    return (
        float(np.abs(sol.channels["z.value"] - z).max()),
        float(np.abs(np.abs(sol.channels["f.value"]) - c * z).max()),
    )


@pytest.mark.parametrize("kind", [ml.Kinematic, ml.QuasiStatic], ids=["kinematic", "quasi-static"])
def test_element_state_follows_a_prescribed_motion(kind) -> None:
    """A lag of the driven travel x = a t (a = 2 m/s, tau = 0.1 s): z = a (t - tau (1 -
    exp(-t/tau))) (closed form), advanced by the trapezoidal rule between the output rows:
    at h = 5 ms within 2e-5 m (measured 1.53e-5 m), second order (h/2: error / 4, measured
    ratio 4.00). The drive holds the element's force c z at the advanced state (|effort| =
    c z within c * 2e-5 N): the reactions see the advanced state too."""
    z_err, f_err = _lag_error(kind(end=0.5, step=0.005))
    assert z_err < 2e-5 and f_err < 50.0 * 2e-5
    z_half, _ = _lag_error(kind(end=0.5, step=0.0025))
    assert 3.9 < z_err / z_half < 4.1


def test_static_keeps_initial_element_states() -> None:
    """A static analysis solves one instant: no time to integrate over, the state keeps its
    initial value (0) while the travel is a t = 0.6 m."""
    sol = ml.solve(
        _driven_slider(0.1, 2.0, 50.0),
        ml.Static(time=0.3),
        requests=[ml.ElementOutput("z", "lag"), ml.JointCoordinate("x", "g", "travel")],
    )
    assert sol.ok
    assert sol.channels["z.value"][0] == 0.0
    assert sol.channels["x.value"][0] == pytest.approx(0.6, abs=1e-12)


@dataclass
class AnalyticLag(Lag):
    """`Lag` with its own state Jacobian d(dz/dt)/dz = -1/tau, counting its calls."""

    calls: int = 0

    def state_jacobian(self, view, z) -> np.ndarray:
        self.calls += 1
        return np.array([[-1.0 / self.tau]])


def test_state_jacobian_of_an_element_is_used_and_gives_the_same_motion() -> None:
    """An element's `state_jacobian` replaces the differenced block (it is called) and the
    state history equals the one with differences within 1e-12 of F0 (linear rates: the
    difference quotient is exact to rounding)."""
    from mechlib.elements.states import ElementStates

    element = AnalyticLag("lag", "s", 0.1, 4.0)
    states = ElementStates([element])
    states.start(None)
    states.advance(None, 0.01)
    assert element.calls == 1
    assert states.trial[0] == pytest.approx(4.0 * 0.01 / (0.1 + 0.005), rel=1e-12)
    mech = _slider(0.1)
    analytic = _slider(0.1)
    analytic.forces["lag"] = AnalyticLag("lag", "s", 0.1, 4.0)
    runs = [
        ml.solve(m, ml.Dynamic(end=0.3, step=0.01), requests=[ml.ElementOutput("z", "lag")])
        for m in (mech, analytic)
    ]
    assert np.abs(runs[0].channels["z.value"] - runs[1].channels["z.value"]).max() < 4e-12
