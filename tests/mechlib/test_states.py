"""Element states: first-order ODEs integrated with the mechanism (issue 3 item 10).

Reference: a force that builds up as a first-order lag, tau dz/dt + z = F0, pushing a slider
of mass m from rest: z = F0 (1 - exp(-t/tau)), x = F0/m (t^2/2 - tau t + tau^2 (1 -
exp(-t/tau))) (integrate twice).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

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
    output_units = {"value": "N"}

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
    sol = ml.solve(_slider(tau), ml.Dynamic(end=0.5, step=0.01, tolerance=1e-8),
                   requests=[ml.ElementOutput("z", "lag"), ml.JointCoordinate("x", "g", "travel")])
    t = sol.time
    z = F0 * (1 - np.exp(-t / tau))
    x = F0 / m * (t * t / 2 - tau * t + tau * tau * (1 - np.exp(-t / tau)))
    assert np.abs(sol.channels["z.value"] - z).max() < 1e-5 * F0
    assert np.abs(sol.channels["x.value"] - x).max() < 1e-5 * x.max()


def test_stiff_state_stays_bounded() -> None:
    """tau = 1e-4 s with outputs every 10 ms: no failure, the state never exceeds F0 by
    more than 1 % (A-stable trapezoidal rule) and ends at F0."""
    sol = ml.solve(_slider(1e-4), ml.Dynamic(end=0.5, step=0.01),
                   requests=[ml.ElementOutput("z", "lag")])
    z = sol.channels["z.value"]
    assert sol.ok
    assert z.max() <= 4.0 * 1.01
    assert abs(z[-1] - 4.0) < 1e-3
