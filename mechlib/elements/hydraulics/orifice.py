"""Orifice flows of a critically centred 4-land spool and the pressure floor (SI units):
the laws of mechlib.elements.hydraulics.laws (regularised root, floor, flows), with the
flows as a record for the element's outputs.
"""

from __future__ import annotations

from dataclasses import dataclass

from mechlib.elements.hydraulics.laws import floored, orifice_flows, regularised_root

__all__ = ["SpoolFlows", "floored", "regularised_root", "spool_flows"]


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
    (`supply`: mechlib.elements.hydraulics.Supply) and chambers at p1, p2 (Pa); K = `gain`
    (laws.orifice_flows)."""
    flows = orifice_flows(
        opening, p1, p2, supply.pressure, supply.return_pressure, gain, transition
    )
    return SpoolFlows(*flows)
