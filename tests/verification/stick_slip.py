"""Independent reference for one-degree-of-freedom motion with exact Coulomb stick/slip.

Plain SciPy, no engine code: `solve_ivp` (DOP853, rtol 1e-12) integrates the sliding
motion with the friction opposing the velocity, stops at every zero of the velocity
(an event), and there decides exactly: the joint sticks for good when the load to be held
is within the static friction capacity (loads here do not depend on time), else it slides
on in the direction of that load. No regularisation anywhere.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["OneDof", "StickSlipHistory", "friction_pendulum", "integrate_stick_slip"]


@dataclass(frozen=True)
class OneDof:
    """`sliding(x, v, direction)`: acceleration while sliding in `direction` (+1/-1), the
    friction opposing it; `held(x)`: (load to hold at rest, friction capacity at rest)."""

    sliding: Callable[[float, float, float], float]
    held: Callable[[float], tuple[float, float]]


@dataclass
class StickSlipHistory:
    """Dense solution pieces, turning points (t, x) and where/when it stuck for good."""

    pieces: list
    turns: list
    stuck_at: tuple[float, float] | None

    def position(self, t: np.ndarray) -> np.ndarray:
        out = np.full(np.shape(t), np.nan)
        for t0, t1, sol in self.pieces:
            inside = (t >= t0) & (t <= t1)
            out[inside] = sol(t[inside])[0]
        if self.stuck_at is not None:
            out[t >= self.stuck_at[0]] = self.stuck_at[1]
        return out


def integrate_stick_slip(system: OneDof, x0: float, v0: float, end: float) -> StickSlipHistory:
    """Motion from (x0, v0) over [0, end] with exact stick/slip switching."""
    t, x, v = 0.0, x0, v0
    pieces, turns = [], []
    while t < end:
        if v == 0.0:
            load, capacity = system.held(x)
            if abs(load) <= capacity:
                return StickSlipHistory(pieces, turns, (t, x))
            direction = float(np.sign(load))
        else:
            direction = float(np.sign(v))

        def rhs(_t, y, d=direction):
            return [y[1], system.sliding(y[0], y[1], d)]

        def stops(_t, y, d=direction):  # the velocity falls through zero
            return y[1] * d

        stops.terminal, stops.direction = True, -1
        sol = solve_ivp(
            rhs,
            (t, end),
            [x, v],
            method="DOP853",
            rtol=1e-12,
            atol=1e-14,
            dense_output=True,
            events=stops,
        )
        pieces.append((t, sol.t[-1], sol.sol))
        if sol.status != 1:
            break
        t, x, v = float(sol.t_events[0][0]), float(sol.y_events[0][0][0]), 0.0
        turns.append((t, x))
    return StickSlipHistory(pieces, turns, None)


def friction_pendulum(
    mass: float, length: float, mu_r: float, preload: float, g: float = 9.81
) -> OneDof:
    """A uniform bar (mass kg, length m) hinged at one end, angle x from the horizontal
    (gravity -y), pin friction T = mu_r |F| + preload (N*m) with F the hinge force, which
    depends on the angular acceleration itself: solved by fixed-point iteration (the
    friction's share mu_r m L / 2 is tiny against the inertia m L^2 / 3)."""
    inertia, arm = mass * length**2 / 3.0, length / 2.0

    def hinge_force(x: float, v: float, a: float) -> float:
        acm = arm * (
            a * np.array([-np.sin(x), np.cos(x)]) - v * v * np.array([np.cos(x), np.sin(x)])
        )
        return float(np.linalg.norm(mass * acm + np.array([0.0, mass * g])))

    def sliding(x: float, v: float, direction: float) -> float:
        a = 0.0
        for _ in range(100):
            new = (
                -mass * g * arm * np.cos(x) - direction * (mu_r * hinge_force(x, v, a) + preload)
            ) / inertia
            if abs(new - a) <= 1e-15 * max(1.0, abs(new)):
                return new
            a = new
        return a

    def held(x: float) -> tuple[float, float]:
        return -mass * g * arm * np.cos(x), mu_r * mass * g + preload

    return OneDof(sliding, held)
