"""A dense row without its position projection (`Dynamic.project_rows` False), for a run
whose rows only serve a comparison (an accuracy companion: loadcases.run.companion).

The row's (q, qd) are the quintic Hermite interpolant of the step's ends (error O(h^6) in
q), left where it lies: the integrator leaves its steps on the position constraints to
1e-9 (median; 1e-10 to 1e-6) and the interpolant between them within its own error of
them, so Newton's projection (mechlib.solvers.dense_compiled: two iterations with the
constraint Jacobian, about half of a row's cost) moves q by no more than that. The
velocities are still projected onto phi_q qd = nu and the accelerations and reactions
still solved from the equations of motion at the row's state (the same kernel as a
projected row's), so that a request reads the loads of that state. Where the kernel gives
up (`FALLBACK`: a matrix not clearly well conditioned, a number not finite) the caller
takes the projected row instead.
"""

from __future__ import annotations

import numpy as np

from mechlib.core.jit import KERNEL, njit
from mechlib.kinematics import constraint_arrays as ca
from mechlib.solvers.dense_compiled import FALLBACK, _dynamics, _schur, interpolated

__all__ = ["unprojected_row"]


@njit(**KERNEL)
def unprojected_row(ends, h, s, ints, floats, functions, refs, body, z, elements, out):
    """The row at the fraction s of a step of h (s) with ends (6, nq) (dense_compiled.
    interpolated), its q as interpolated, its qd, qdd and lam as a projected row's there
    (`elements`: the packed force elements at element states z). Writes (q, qd, qdd, lam)
    stacked into `out`; returns (DONE or FALLBACK, Jacobians evaluated)."""
    q, qd = interpolated(ends, h, s)
    nq = q.shape[0]
    nb, m = nq // 7, ints[7]
    if not (np.isfinite(q).all() and np.isfinite(qd).all()):
        return FALLBACK, 0
    x, xd = ca.state_arrays(q, qd, nb)
    phi, jac = np.empty(m), np.empty((m, nq))
    ca.phi_and_jacobian(x, ints, floats, functions, refs, phi, jac)
    ok, minv, weighted, low = _schur(x, jac, body, nb)
    if not ok:
        return FALLBACK, 1
    return _dynamics(q, qd, x, xd, jac, minv, weighted, low, ints, floats, functions, refs,
                     body, z, elements, out), 1  # fmt: skip
