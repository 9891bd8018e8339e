"""The mechanism a solve works on: its own copy of the force elements, so that event
activations (`active`), contact and friction memory and bindings to the solve's System
never leak into the caller's Mechanism. Bodies, points, joints, motions and frames are not
changed by a solve and are shared. Copying the elements costs about 0.1 ms each."""

from __future__ import annotations

import copy
import dataclasses

from mechlib.model.mechanism import Mechanism

__all__ = ["solve_copy"]


def solve_copy(mechanism: Mechanism) -> Mechanism:
    """`mechanism` with deep copies of its force elements (same names, same order)."""
    forces = {name: copy.deepcopy(element) for name, element in mechanism.forces.items()}
    return dataclasses.replace(mechanism, forces=forces)
