"""Some rows of the constraint Jacobian without the others: an element that reads the
reaction of one joint (joint friction: the force block of its own rows) at a state whose
phi_q is not known needs only the equation groups that hold those rows. A flexible body's
weld rows and the coordinate block are most of the cost of a whole phi_q, and a joint's own
rows are neither (a lock on a joint is a coordinate row, evaluated when asked for). The rows
are those of `System.phi_q`, bit for bit: each group writes its own block alike."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from mechlib.kinematics.kin import Kin

if TYPE_CHECKING:
    from mechlib.system.system import System

__all__ = ["Plan", "phi_q_rows"]

_KEPT_PLANS = 64
Plan = tuple[Any, int, np.ndarray, np.ndarray]  # group (None: the coordinate block), ...


def phi_q_rows(system: System, k: Kin, rows: np.ndarray) -> np.ndarray:
    """phi_q[rows] (len(rows), nq) of the active equations `rows` (indices among them), by
    the equation groups that hold them only (packed systems: one compiled call, whole)."""
    if system.packed_constraints() is not None:
        return system.phi_q(k)[rows]
    out = np.empty((len(rows), k.ncol))
    for group, size, taken, at in _plan(system, rows):
        block = np.zeros((size, k.ncol))
        if group is None:
            system.coordinate_rows().jacobian(k, block)
        else:
            group.jacobian(k, block)
        out[at] = block[taken]
    return system.body_columns(out)


def _plan(system: System, rows: np.ndarray) -> list[Plan]:
    """(group or None for the coordinate block, its size, the rows taken from its block,
    their places among `rows`) for each group holding some of `rows`, found once per set
    of active equations (System.row_plans)."""
    key = (system.active.tobytes(), rows.tobytes())
    found = system.row_plans.get(key)
    if found is not None:
        return found
    wanted = system.active[rows]
    found, start = [], 0
    for group in [*system.groups, None]:
        end = len(system._all_labels) if group is None else start + group.size
        inside = np.flatnonzero((wanted >= start) & (wanted < end))
        if inside.size:
            found.append((group, end - start, wanted[inside] - start, inside))
        start = end
    if len(system.row_plans) >= _KEPT_PLANS:  # sets of active rows change with events
        system.row_plans.clear()
    system.row_plans[key] = found
    return found
