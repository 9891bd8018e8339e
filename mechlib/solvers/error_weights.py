"""The error scale of every state: the size (in the state's own unit) against which the
local error test of generalized-alpha weighs its error, one rule for all of them (Radau,
the cross-check integrator, keeps scipy's scalar absolute tolerances, docs/analyses.md).

A state's error weight is tolerance x (scale + |value|): the scale is the absolute part,
the state's own size, so that a state that moves on a small scale of its own (a 19 um
oil-column oscillation on a 1 m rig, a modal coordinate, a spool) is resolved to the
tolerance of its own size, not of the mechanism's.

- Body translations (m): the mechanism's size `System.length`.
- Body rotations: 1 rad (an Euler parameter changes by half an angle: weight 1).
- Modal coordinates (kg^0.5 m): sqrt(body mass) x the mechanism's size (`modal_scales`).
- Element states: the scales their element declares (`state_scales()`: a servo-actuator's
  chamber pressures by its supply pressure, its spool by its rated opening); the states of
  an element that declares none, or whose states no force reads (an integral kept as an
  output, a clearance joint's wear work), take no part in the test (scale infinite).
"""

from __future__ import annotations

import numpy as np

from mechlib.system.system import System

__all__ = ["coordinate_scales", "element_state_scales", "modal_scales"]


def coordinate_scales(system: System) -> np.ndarray:
    """The scale of each entry of q (nq,): bodies' translations (m) and rotations, then the
    flexible bodies' modal coordinates (kg^0.5 m)."""
    length = system.length
    bodies = np.tile(system.body_weights(length, 1.0), system.nb)
    modal = [modal_scales(a.body.component, length) for a in system.flexible]
    return np.concatenate([bodies, *modal])


def modal_scales(component, length: float) -> np.ndarray:
    """Per mode (n,), kg^0.5 m: sqrt(body mass) x the mechanism's size `length` (m), the
    modal coordinate of a displacement of the body's mass by that size (mass-normalised
    modes). A static deflection scale under the body's own weight (g / omega_1^2) was
    tried and not kept: a component carries other masses (an arm's end mass, a panel's
    hinge loads), whose deflection its own weight does not measure (the offset-arm
    verification, whose 0.65 g beam carries a mass, took 16x the time)."""
    return np.full(len(component.frequencies), np.sqrt(component.mass) * length)


def element_state_scales(elements, count: int) -> np.ndarray:
    """The scale of each element state (count,), in the order of
    `mechlib.elements.states.ElementStates` (the elements' own order): an element's
    `state_scales()`, infinite for an element that declares none or whose states drive no
    force."""
    out = []
    for e in elements:
        n = int(getattr(e, "n_states", 0))
        if not n:
            continue
        declared = getattr(e, "state_scales", None)
        if declared is None or not getattr(e, "states_drive_forces", True):
            out.append(np.full(n, np.inf))
        else:
            out.append(np.asarray(declared(), float).reshape(n))
    return np.concatenate(out) if out else np.zeros(count)
