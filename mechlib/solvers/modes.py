"""Modes: natural frequencies and mode shapes linearised about a static equilibrium.

At the equilibrium (q, lam) of `Static(time)`, the tangent stiffness K = d(phi_q^T lam - Q)/dq
(forward differences, as the static analysis) and the mass matrix M are restricted to the
motions the constraints allow, q = q0 + N x with N a basis of the null space of phi_q
(normalisation rows included): (N^T K N) x = w^2 (N^T M N) x. Frequencies f = w / (2 pi) in
Hz, lowest first; a negative w^2 (an unstable equilibrium) is reported as a negative
frequency -sqrt(-w^2)/(2 pi). Mode shapes are mass-normalised.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from mechlib.core.work import count
from mechlib.model.analysis import Modes
from mechlib.solvers.static.balance import Balance
from mechlib.solvers.static.equilibrium import equilibrium
from mechlib.system.system import System

__all__ = ["ModalResult", "Modes", "modal_channels", "normal_modes"]


@dataclass(frozen=True)
class ModalResult:
    """Normal modes about the equilibrium q at `time` (s): `frequencies` (n,) in Hz, lowest
    first (negative: unstable), `shapes` (n, nq) as dq per unit modal amplitude."""

    time: float
    q: np.ndarray
    frequencies: np.ndarray
    shapes: np.ndarray

    def first(self, count: int | None) -> ModalResult:
        """The `count` lowest modes (all when None)."""
        n = len(self.frequencies) if count is None else min(count, len(self.frequencies))
        return ModalResult(self.time, self.q, self.frequencies[:n], self.shapes[:n])


def normal_modes(system: System, q0: np.ndarray, time: float, stats) -> ModalResult:
    """The modes about the static equilibrium at `time` (s) found from q0."""
    q, lam = equilibrium(system, q0, None, time, stats)
    k = system.kin(q, None, time)
    jac = system.phi_q(k)
    stiffness = Balance(system, time, q).stiffness(q, lam)
    count(factorizations=2)  # the null-space SVD and the eigen-decomposition
    basis = sla.null_space(jac)
    kr = basis.T @ stiffness @ basis
    mr = basis.T @ system.mass(k) @ basis
    w2, x = sla.eigh(0.5 * (kr + kr.T), 0.5 * (mr + mr.T))
    freq = np.sign(w2) * np.sqrt(np.abs(w2)) / (2.0 * np.pi)
    stats.steps += 1
    return ModalResult(time, q, freq, (basis @ x).T)


def modal_channels(system: System, modes: ModalResult, requests) -> dict[str, np.ndarray]:
    """One row per mode: `mode.number`, `mode.frequency` (Hz), then for each point request
    its modal displacement x y z (m per unit modal amplitude) and for each joint coordinate
    request its modal angle or travel (`value`); other requests have no modal meaning here."""
    from mechlib.core.rotation import d_rotate
    from mechlib.outputs.requests import JointCoordinate, PointKinematics

    freq, shapes = modes.frequencies, modes.shapes
    k = system.kin(modes.q, None, modes.time)
    out = {"mode.number": np.arange(1.0, len(freq) + 1.0), "mode.frequency": freq.copy()}
    for req in requests:
        if isinstance(req, PointKinematics):
            b, s = system.point(req.point)
            if b == system.nb:
                disp = np.zeros((len(freq), 3))
            else:
                block = np.hstack([np.eye(3), d_rotate(k.p[b], s)])
                disp = shapes[:, 7 * b : 7 * b + 7] @ block.T
            axes = system.frame_axes(req.frame, k)
            out.update(zip((f"{req.name}.{c}" for c in "xyz"), (disp @ axes).T))
        elif isinstance(req, JointCoordinate):
            kind = "angle" if req.quantity in ("angle", "omega", "alpha") else "travel"
            grad = system.coordinate_gradient(system.measure(req.joint, kind), k)
            out[f"{req.name}.value"] = shapes @ grad
    return out
