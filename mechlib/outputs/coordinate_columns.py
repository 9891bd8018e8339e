"""Joint coordinates (angle, travel and their rates) of every recorded row at once.

The measures' own compiled kernels (mechlib.kinematics.kernels) run once on the rows'
body states stacked one after the other, so each value is computed by the same
arithmetic as row by row (`JointCoordinate` through `AngleMeasure.value` ...): angles
and travels and their first rates are bit for bit those; the second rates sum the same
terms in another order (d(theta)/dq . qdd is taken as the rate with qdd in place of qd),
equal to rounding.
"""

from __future__ import annotations

import math

import numpy as np

from mechlib.kinematics import kernels as kr
from mechlib.kinematics.coordinates import TWO_PI, AngleMeasure, angle_quad
from mechlib.kinematics.kin import GROUND_Q

__all__ = ["coordinate_column", "stacked_bodies"]

_KIND = {"angle": "angle", "omega": "angle", "alpha": "angle"}
_ORDER = {"angle": 0, "travel": 0, "omega": 1, "speed": 1, "alpha": 2, "accel": 2}


def stacked_bodies(rows: np.ndarray, nb: int, ground: np.ndarray) -> np.ndarray:
    """Per-body rows (n * (nb+1), 7) of n stacked states (n, 7 nb + nz): each row's moving
    bodies then `ground` (7,), as `Kin.from_state` lays out one."""
    n = rows.shape[0]
    x = np.empty((n, nb + 1, 7))
    x[:, :nb] = rows[:, : 7 * nb].reshape(n, nb, 7)
    x[:, nb] = ground
    return x.reshape(-1, 7)


def _group(kernel: str, group, nb: int, n: int, *states: np.ndarray) -> np.ndarray:
    """`kernel` (phi, rate, gamma) of a constraint group's k items in each of n stacked
    states: (n, k)."""
    bi, bj, *vectors = group.args
    first = (np.arange(n, dtype=np.int64) * (nb + 1))[:, None]
    args = [(first + bi[None, :]).ravel(), (first + bj[None, :]).ravel()]
    args += [np.tile(v, (n, 1)) for v in vectors]
    out = np.empty(n * bi.shape[0])
    getattr(kr, f"{group.prefix}_{kernel}")(*states, *args, out)
    return out.reshape(n, -1)


def coordinate_column(system, trajectory, joint: str, quantity: str) -> np.ndarray:
    """angle|omega|alpha (rad, rad/s, rad/s^2) or travel|speed|accel (m, m/s, m/s^2) of
    `joint` at every recorded row (n,); an angle unwrapped against each row's reference."""
    measure = system.measure(joint, _KIND.get(quantity, "travel"))
    n, nb, order = len(trajectory), system.nb, _ORDER[quantity]
    x = stacked_bodies(trajectory.stacked("q"), nb, GROUND_Q)
    group = measure.sine_cosine if isinstance(measure, AngleMeasure) else measure.distance
    parts = [_group("phi", group, nb, n, x)]
    if order:
        xd = stacked_bodies(trajectory.stacked("qd"), nb, np.zeros(7))
        parts.append(_group("rate", group, nb, n, x, xd))
    if order == 2:
        xdd = stacked_bodies(trajectory.stacked("qdd"), nb, np.zeros(7))
        parts += [_group("rate", group, nb, n, x, xdd), -_group("gamma", group, nb, n, x, xd)]
    if not isinstance(measure, AngleMeasure):
        return parts[order][:, 0] if order < 2 else parts[2][:, 0] + parts[3][:, 0]
    s, c = parts[0][:, 0], parts[0][:, 1]
    if order == 0:
        # math.atan2, as AngleMeasure.value: numpy's own arctan2 may differ by an ulp
        raw = np.fromiter(map(math.atan2, s.tolist(), c.tolist()), float, n)
        reference = trajectory.references.angle_references((joint, "angle"))
        return raw + TWO_PI * np.round((reference - raw) / TWO_PI)
    sd, cd = parts[1][:, 0], parts[1][:, 1]
    if order == 1:
        return (c * sd - s * cd) / (s * s + c * c)
    s_qdd, c_qdd = parts[2][:, 0], parts[2][:, 1]
    along = (c * s_qdd - s * c_qdd) / (s * s + c * c)
    return along + angle_quad(s, c, sd, cd, parts[3][:, 0], parts[3][:, 1])
