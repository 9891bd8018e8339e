"""Orifice flows of a critically centred 4-land spool, the pressure floor and the piston
friction law (SI units).

Regularised root sr(dp) = dp / (dp^2 + dp_tr^2)^(1/4): sign(dp) sqrt(|dp|) for
|dp| >> dp_tr, linear (laminar) below, with a finite derivative at dp = 0 where the plain
root's is infinite (a Newton iteration on the pressures would stall there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["SpoolFlows", "floored", "regularised_root", "spool_flows"]


def regularised_root(dp: float, transition: float) -> float:
    """sr(dp) (Pa^0.5) with the laminar transition `transition` (Pa)."""
    return dp / (dp * dp + transition * transition) ** 0.25


def floored(p: float, floor: float, width: float) -> float:
    """p (Pa) floored smoothly at `floor`: floor + width * softplus((p - floor)/width)."""
    s = (p - floor) / width
    return floor + width * (s + math.log1p(math.exp(-s)) if s > 0.0 else math.log1p(math.exp(s)))


@dataclass(frozen=True)
class SpoolFlows:
    """Flows (m^3/s) of the spool: q1 into chamber 1, q2 out of chamber 2, q_supply from
    the supply port, q_return to the return port; `throttling` (W): the power dissipated in
    the two open lands."""

    q1: float
    q2: float
    q_supply: float
    q_return: float
    throttling: float


def spool_flows(
    opening: float, p1: float, p2: float, supply, gain: float, transition: float
) -> SpoolFlows:
    """Critically centred spool at normalised `opening` (1: rated) between the supply
    (`supply`: mechlib.elements.hydraulics.Supply) and chambers at p1, p2 (Pa); K = `gain`.

    opening >= 0: supply -> 1 and 2 -> return, q1 = K x sr(p_s - p1), q2 = K x sr(p2 - p_r);
    opening < 0: 1 -> return and supply -> 2, q1 = K x sr(p1 - p_r), q2 = K x sr(p_s - p2).
    """
    ps, pr = supply.pressure, supply.return_pressure
    if opening >= 0.0:
        inlet, outlet = ps - p1, p2 - pr
    else:
        inlet, outlet = p1 - pr, ps - p2
    root_in, root_out = regularised_root(inlet, transition), regularised_root(outlet, transition)
    q_in, q_out = gain * opening * root_in, gain * opening * root_out
    throttling = abs(gain * opening) * (root_in * inlet + root_out * outlet)
    if opening >= 0.0:
        q1, q2, q_supply, q_return = q_in, q_out, q_in, q_out
    else:
        q1, q2, q_supply, q_return = q_in, q_out, -q_out, -q_in
    return SpoolFlows(q1, q2, q_supply, q_return, throttling)
