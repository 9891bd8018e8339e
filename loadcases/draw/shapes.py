"""Shapes shared by the pictures and the 3-D page: spring zigzags and body outlines."""

from __future__ import annotations

import numpy as np

__all__ = ["frame_indices", "outline_order", "zigzag"]

_ZIGZAG_TEETH = 8
_ZIGZAG_WIDTH = 0.05
"""half width of a tooth, as a fraction of the spring's length."""


def zigzag(a: np.ndarray, b: np.ndarray, side: np.ndarray) -> np.ndarray:
    """Points (k, d) of a zigzag from a to b (d = 2 or 3 coordinates, m); its teeth stand
    out along the unit vector `side` (perpendicular to b - a) by a twentieth of the length."""
    d = b - a
    length = float(np.linalg.norm(d))
    if length < 1e-9:
        return np.array([a, b])
    s = np.linspace(0.15, 0.85, 2 * _ZIGZAG_TEETH + 1)
    out = np.where(np.arange(s.size) % 2 == 1, 1.0, -1.0)
    out[0] = out[-1] = 0.0
    middle = a + np.outer(s, d) + np.outer(out, _ZIGZAG_WIDTH * length * side)
    return np.vstack([a, middle, b])


def outline_order(pts: np.ndarray) -> list[int]:
    """Indices of the distinct 2-D points `pts` (k, 2) in order round their centre, the
    first repeated at the end (a closed outline); one or two distinct points: those."""
    _, first = np.unique(np.round(pts, 9), axis=0, return_index=True)
    first = np.sort(first)
    if len(first) <= 2:
        return first.tolist()
    unique = pts[first]
    centre = unique.mean(axis=0)
    order = first[np.argsort(np.arctan2(*(unique - centre).T[::-1]))].tolist()
    return order + order[:1]


def frame_indices(count: int, limit: int) -> list[int]:
    """At most `limit` output indices of `count`, evenly spread, first and last included."""
    return sorted(set(np.linspace(0, count - 1, min(count, limit)).round().astype(int).tolist()))
