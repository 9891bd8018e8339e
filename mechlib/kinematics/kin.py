"""Per-body kinematic arrays of one state, ground appended as the last body.

Symbols: ``q`` stacks ``[r_b, p_b]`` (7 per moving body; r in m, p Euler parameters),
``qd`` their rates; the modal coordinates of flexible bodies (mechlib.flexible) follow
them in ``q`` and are ``z``, ``zd`` here. Ground is body index ``nb`` with r = 0,
p = (1, 0, 0, 0) and no columns in the Jacobians that leave this module (its 7 columns are
cut out: `System.body_columns`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["GROUND_Q", "Kin"]

GROUND_Q = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
_NO_MODES = np.zeros(0)
_NO_MODES.flags.writeable = False


class Kin:
    """`x` (nb+1, 7) rows [r, p] and `xd` their rates; r, p, rd, pd are views of them.
    `at_rest`: an equilibrium (static, quasi-static), built without rates: its rates are zero
    and force elements leave out what acts on rates (a servo's oil-column damping)."""

    __slots__ = ("at_rest", "t", "x", "xd", "z", "zd")

    def __init__(
        self,
        x: np.ndarray,
        xd: np.ndarray,
        t: float = 0.0,
        at_rest: bool = False,
        z: np.ndarray | None = None,
        zd: np.ndarray | None = None,
    ):
        self.x, self.xd, self.t, self.at_rest = x, xd, t, at_rest
        self.z = _NO_MODES if z is None else z  # modal coordinates of flexible bodies
        self.zd = _NO_MODES if zd is None else zd

    r = property(lambda self: self.x[:, :3])
    p = property(lambda self: self.x[:, 3:])
    rd = property(lambda self: self.xd[:, :3])
    pd = property(lambda self: self.xd[:, 3:])

    @property
    def nb(self) -> int:
        """Number of moving bodies."""
        return self.x.shape[0] - 1

    @property
    def ncol(self) -> int:
        """Columns of the working Jacobian (ground included, modal coordinates after it)."""
        return 7 * self.x.shape[0] + self.z.shape[0]

    @classmethod
    def from_state(
        cls, q: np.ndarray, qd: np.ndarray | None = None, t: float = 0.0, nz: int = 0
    ) -> Kin:
        """Split the stacked state (7 nb + nz,) into per-body rows with ground appended and
        the `nz` modal coordinates at its end; without `qd`, a state at rest."""
        n = q.shape[0] - nz
        x = np.empty(n + 7)
        x[:n] = q[:n]
        x[n:] = GROUND_Q
        xd = np.zeros(n + 7)
        if qd is not None:
            xd[:n] = qd[:n]
        if nz == 0:
            return cls(x.reshape(-1, 7), xd.reshape(-1, 7), t, at_rest=qd is None)
        zd = np.zeros(nz) if qd is None else np.array(qd[n:], dtype=float)
        return cls(
            x.reshape(-1, 7),
            xd.reshape(-1, 7),
            t,
            at_rest=qd is None,
            z=np.array(q[n:], dtype=float),
            zd=zd,
        )
