"""The constraint Jacobian of a 3-D system as its non-zeros (`SparseRows`), for the checks
of a large mechanism: a chain of N bodies has O(N) non-zeros among O(N^2) entries, which
the dense `System.phi_q` would allocate and fill (1.8 GB for 2000 bodies).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mechlib.kinematics.kin import Kin
from mechlib.linalg.sparse_rows import SparseRows
from mechlib.system.planar_kernels import planar_reduce

if TYPE_CHECKING:
    from mechlib.system.system import System

__all__ = ["planar_reduced", "sparse_phi_q"]

_CHUNK = 16  # rows reduced at once by `planar_reduced`: the kernel loops over rows x bodies


def _dense_entries(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r, c = np.nonzero(rows)
    return r, c, rows[r, c]


def sparse_phi_q(system: System, k: Kin) -> SparseRows:
    """`system.phi_q(k)` as its non-zeros: the active rows, without ground's columns.

    The primitive groups give their entries a few items at a time
    (`mechlib.kinematics.constraints`); the weld equations of flexible bodies and the
    coordinate equations (a few rows) are evaluated as dense rows."""
    parts, row = [], 0
    for group in system.groups:
        if hasattr(group, "entries"):
            r, c, v = group.entries(k)
        else:
            block = np.zeros((group.size, k.ncol))
            group.jacobian(k, block)
            r, c, v = _dense_entries(block)
        parts.append((r + row, c, v))
        row += group.size
    block = np.zeros((len(system.coordinates), k.ncol))
    system.coordinate_rows().jacobian(k, block)
    r, c, v = _dense_entries(block)
    parts.append((r + row, c, v))
    rows, cols, values = (np.concatenate(column) for column in zip(*parts))
    # the active rows (System._select) and the working columns (System.body_columns)
    position = np.full(row + len(system.coordinates), -1)
    position[system.active] = np.arange(system.active.size)
    ground = 7 * system.nb
    column = np.full(k.ncol, -1)
    column[:ground] = np.arange(ground)
    column[ground + 7 :] = np.arange(ground, ground + k.ncol - ground - 7)
    kept = (position[rows] >= 0) & (column[cols] >= 0)
    shape = (int(system.active.size), int(system.nq))
    return SparseRows.of(position[rows[kept]], column[cols[kept]], values[kept], shape)


def planar_reduced(
    rows: SparseRows, x: np.ndarray, e_in: np.ndarray, normal: np.ndarray
) -> SparseRows:
    """`rows` (m, 7 nb) T of a planar system (m, 3 nb) as non-zeros: the planar reduction
    kernel run on `_CHUNK` rows at a time over only the bodies they touch (x: the bodies'
    positions (nb + 1, 7); e_in (3, 2), normal (3,): the plane)."""
    parts = []
    bounds = rows.bounds
    for first in range(0, rows.shape[0], _CHUNK):
        last = min(first + _CHUNK, rows.shape[0])
        span = slice(bounds[first], bounds[last])
        bodies = np.unique(rows.cols[span] // 7)
        local = np.zeros((last - first, 7 * bodies.size))
        where = 7 * np.searchsorted(bodies, rows.cols[span] // 7) + rows.cols[span] % 7
        local[rows.rows[span] - first, where] = rows.values[span]
        out = np.zeros((last - first, 3 * bodies.size))
        planar_reduce(local, x[bodies], e_in, normal, out)
        r, c = np.nonzero(out)
        parts.append((r + first, 3 * bodies[c // 3] + c % 3, out[r, c]))
    if not parts:
        return SparseRows.of(np.empty(0), np.empty(0), np.empty(0), (rows.shape[0], 0))
    r, c, v = (np.concatenate(column) for column in zip(*parts))
    return SparseRows.of(r, c, v, (rows.shape[0], 3 * (rows.shape[1] // 7)))
