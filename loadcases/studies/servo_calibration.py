"""Calibration of a position servo-actuator as seed 004 section 6.2 does it: the actuator
isolated on an equivalent mass (the load's inertia seen at the rod, fig. 6.9), its PI
gains from the Ziegler-Nichols closed-loop method (fig. 6.10).

`transmission` reads a kinematic run of the mechanism driven along the actuator: the
transmission ratio dL/dtheta (m/rad) from the actuator's and the output joint's rates, and
the equivalent mass m_eq = 2 T / L'^2 (kg) from the run's kinetic energy T (the energy
request): the mass that, moving with the rod, stores the mechanism's kinetic energy.

`ziegler_nichols` closes the loop with proportional gain only (K_i = 0) on the
actuator moving `mass` (kg) on a slider, commands a small step, and measures the growth
rate sigma (1/s) of the oscillation that follows from its successive error peaks; the
ultimate gain K_u is where sigma changes sign (bisection in log K), the ultimate period T_u
twice the spacing of the peaks there. The Ziegler-Nichols PI rule (Ziegler & Nichols,
Optimum settings for automatic controllers, Trans. ASME 64, 1942): K_p = 0.45 K_u,
T_i = T_u / 1.2, so K_i = K_p / T_i (the controller integrates the error in m*s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

import mechlib as ml
from mechlib.elements.hydraulics import ServoActuator

__all__ = ["LoopGrowth", "ZieglerNichols", "loop_growth", "transmission", "ziegler_nichols"]

_DOUBLINGS = 12  # factor 4096 above the starting gain for an unstable bracket


@dataclass(frozen=True)
class LoopGrowth:
    """Growth rate sigma (1/s; < 0 decays, -inf: no oscillation) and period (s, NaN
    without one) of the proportional loop's oscillation at gain `kp` (A/m)."""

    kp: float
    sigma: float
    period: float


@dataclass
class ZieglerNichols:
    """Ultimate gain (A/m) and period (s), the Ziegler-Nichols PI gains K_p (A/m) and K_i
    (A/(m*s)), and every loop evaluated, in order."""

    ultimate_gain: float
    ultimate_period: float
    kp: float
    ki: float
    evaluations: list[LoopGrowth] = field(default_factory=list)


def transmission(solution, travel_rate: str, angle_rate: str, kinetic: str, *, floor=0.05):
    """(rows, dL/dtheta (m/rad), m_eq (kg)) of a kinematic run: the columns of the
    actuator's rate (m/s), the output joint's rate (rad/s) and the kinetic energy (J);
    rows where the actuator moves at least `floor` of its largest rate."""
    rate = np.asarray(solution.channels[travel_rate], float)
    omega = np.asarray(solution.channels[angle_rate], float)
    energy = np.asarray(solution.channels[kinetic], float)
    rows = np.abs(rate) >= floor * np.abs(rate).max()
    return rows, rate[rows] / omega[rows], 2.0 * energy[rows] / rate[rows] ** 2


def _rig(actuator: ServoActuator, mass: float, kp: float, step: float) -> ml.Mechanism:
    """`actuator` with gain kp (A/m, no integral) moving `mass` (kg) on a slider along x,
    its stroke demand a step of `step` (m) at t = 0."""
    m = ml.Mechanism()
    m.add_body("rod", mass=mass, cm=(0, 0, 0), inertia=[1, 1, 1])
    m.add_joint("slide", "prismatic", bodies=("rod", "ground"), at=(0, 0, 0), axis=(1, 0, 0))
    points = (("rod", (0.0, 0.0, 0.0)), ("ground", (-0.5, 0.0, 0.0)))
    controller = replace(actuator.controller, kp=kp, ki=0.0)
    m.add_force(
        replace(actuator, name="act", points=points, command=lambda t: step, controller=controller)
    )
    return m


def loop_growth(
    actuator: ServoActuator, mass: float, kp: float, *, step=1e-4, end=0.3, dt=2e-4
) -> LoopGrowth:
    """The proportional loop's response to a step of `step` (m) over `end` (s), outputs
    every `dt` (s): sigma from a straight-line fit of ln|error| at its extrema after the
    first (the step's own approach), the period twice their mean spacing."""
    sol = ml.solve(
        _rig(actuator, mass, kp, step),
        ml.Dynamic(end=end, step=dt),
        requests=[ml.JointCoordinate("x", "slide", "travel")],
    )
    if not sol.ok:  # a loop so unstable that the solver gives up: growing
        return LoopGrowth(kp, math.inf, math.nan)
    t, error = np.asarray(sol.time), step - np.asarray(sol.channels["x.value"])
    slope = np.diff(error)
    turns = np.nonzero(slope[:-1] * slope[1:] < 0.0)[0] + 1
    turns = turns[np.abs(error[turns]) > 1e-9 * step]
    if turns.size < 4:
        return LoopGrowth(kp, -math.inf, math.nan)
    turns = turns[1:]
    sigma = float(np.polyfit(t[turns], np.log(np.abs(error[turns])), 1)[0])
    return LoopGrowth(kp, sigma, 2.0 * float(np.mean(np.diff(t[turns]))))


def ziegler_nichols(
    actuator: ServoActuator, mass: float, *, rtol: float = 0.01, **response
) -> ZieglerNichols:
    """Ultimate gain and period of the proportional loop of `actuator` on `mass` (kg),
    from its controller's K_p up (bisection in log K to `rtol`), and the Ziegler-Nichols
    PI gains; `response`: `loop_growth`'s step, end and dt. ValueError when the loop
    stays stable up to 4096 times the starting gain or is unstable at it."""
    evaluations: list[LoopGrowth] = []

    def grows(kp: float) -> bool:
        evaluations.append(loop_growth(actuator, mass, kp, **response))
        return evaluations[-1].sigma > 0.0

    lo = hi = actuator.controller.kp
    if grows(lo):
        raise ValueError(f"the loop is unstable at the starting gain {lo:g} A/m")
    for _ in range(_DOUBLINGS):
        hi *= 2.0
        if grows(hi):
            break
        lo = hi
    else:
        raise ValueError(f"the loop stays stable up to {hi:g} A/m: no ultimate gain")
    while hi / lo > 1.0 + rtol:
        mid = math.sqrt(lo * hi)
        lo, hi = (lo, mid) if grows(mid) else (mid, hi)
    at = {e.kp: e for e in evaluations}
    periods = [at[k].period for k in (lo, hi) if math.isfinite(at[k].period)]
    ultimate, period = math.sqrt(lo * hi), float(np.mean(periods)) if periods else math.nan
    kp = 0.45 * ultimate
    return ZieglerNichols(ultimate, period, kp, kp * 1.2 / period, evaluations)
