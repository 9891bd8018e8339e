"""The cubic step of MSC Adams (seed 004 eq. 3.10): smooth switches for laws and inputs."""

from __future__ import annotations

from mechlib.core.jit import njit

__all__ = ["compiled_step", "step"]


def step(x: float, x0: float, h0: float, x1: float, h1: float) -> float:
    """h0 for x <= x0, h1 for x >= x1, h0 + (h1 - h0) s^2 (3 - 2 s) between, with
    s = (x - x0) / (x1 - x0) (never divides: the ends are checked first)."""
    if x <= x0:
        return h0
    if x >= x1:
        return h1
    s = (x - x0) / (x1 - x0)
    return h0 + (h1 - h0) * s * s * (3.0 - 2.0 * s)


compiled_step = njit(cache=True, nogil=True)(step)
"""The same step for compiled kernels (contact laws, friction)."""
