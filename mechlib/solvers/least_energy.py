"""Initial velocities of a mechanism with flexible bodies: on the velocity constraints,
the given rates met in least squares, and of the remaining freedom the velocities of least
kinetic energy.

A rigid mechanism's initial velocities are the smallest in the assembly's column norm
(mechlib.solvers.assembly). A flexible body's kept nodes are massless node bodies welded to
it (mechlib.flexible.attached): counted in that norm they pulled the body's frame along to
cancel their modal velocities, and a free beam given only a modal rate started with a rigid
spin and drift of the same order (0.0165 m/s on a free 0.8 m beam given 0.01 kg^0.5 m/s in
its first bending mode). Here the norm is the kinetic energy (the mechanism's mass matrix:
the node bodies weigh nothing, the welds set their velocities), so a free mechanism given
only modal rates keeps its momentum zero, its centre of mass at rest, whatever rigid parts
it carries. The modal coordinates that are not given keep the rigid path's weight besides
(they move only where the constraints need it, as in the positions); a mechanism without
flexible bodies takes the rigid path, unchanged.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import cho_factor, solve_triangular

from mechlib.core.work import count
from mechlib.kinematics.kin import Kin
from mechlib.system.system import System

__all__ = ["least_energy_velocities", "velocity_metric"]

_RANK = 1e-10  # a singular value of phi_q below this x the largest is a dependent row
_RIDGE = 1e-12  # x the largest diagonal of the free directions' Gram matrix: massless ones defined


def velocity_metric(system: System, k: Kin, weights: np.ndarray) -> np.ndarray:
    """The metric (nq, nq) of the remaining freedom in the assembly's scaled columns
    s = qd / weights: the mechanism's mass matrix over its mass (kg/kg, kg m^2/kg: every
    body's, the flexible bodies' frames coupled to their modes, the massless node bodies 0),
    and on the modal coordinates the identity of the rigid path's column norm besides, so
    that a modal coordinate not given moves only where the constraints need it."""
    mass = system.mass(k)
    translations = (7 * np.arange(system.nb)[:, None] + np.arange(3)).ravel()
    total = float(np.trace(mass[np.ix_(translations, translations)])) / 3.0
    metric = mass / max(total, 1e-300) * np.outer(weights, weights)
    modal = np.arange(system.nq - system.nz, system.nq)
    metric[modal, modal] += 1.0
    return metric


def least_energy_velocities(
    jacobian: np.ndarray,
    nu: np.ndarray,
    rows: np.ndarray,
    rhs: np.ndarray,
    metric: np.ndarray,
) -> np.ndarray:
    """qd (nq,) with jacobian qd = nu (least squares where the rows contradict or repeat
    each other), the given `rows` qd = `rhs` in least squares within that, and of what
    remains free the smallest qd^T metric qd."""
    count(factorizations=3 if len(rows) else 2)  # the SVD, the Cholesky, the least squares
    u, s, vt = np.linalg.svd(jacobian, full_matrices=True)
    rank = int(np.sum(s > _RANK * s[0])) if s.size else 0
    particular = vt[:rank].T @ ((u[:, :rank].T @ nu) / s[:rank])
    free = vt[rank:].T  # (nq, f): the velocities the constraints leave free
    if free.shape[1] == 0:
        return particular
    gram = free.T @ metric @ free
    gram += _RIDGE * max(float(np.abs(np.diag(gram)).max()), 1e-300) * np.eye(len(gram))
    lower, _ = cho_factor(gram, lower=True, check_finite=False)
    lower = np.tril(lower)
    shift = solve_triangular(lower, free.T @ metric @ particular, lower=True, check_finite=False)
    if len(rows):
        # the free part is L^-T (v - shift); |v| is the metric norm of qd up to a constant
        mapped = solve_triangular(lower, (rows @ free).T, lower=True, check_finite=False).T
        v, *_ = np.linalg.lstsq(mapped, rhs - rows @ particular + mapped @ shift, rcond=None)
    else:
        v = np.zeros_like(shift)
    return particular + free @ solve_triangular(lower.T, v - shift, lower=False, check_finite=False)
