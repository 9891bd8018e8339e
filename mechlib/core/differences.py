"""The forward-difference step of a differenced Jacobian column: one definition for the
Python and compiled tangents of the dynamic runs, the element states' Newton matrices and
the static balance."""

from __future__ import annotations

from mechlib.core.jit import KERNEL, njit

__all__ = ["FD_STEP", "fd_step"]

FD_STEP = 1e-7  # relative to max(1, |x|): absolute for values below 1


@njit(**KERNEL)
def fd_step(x: float) -> float:
    """The forward-difference step of a variable at value x (in x's units):
    FD_STEP max(1, |x|)."""
    return FD_STEP * max(1.0, abs(x))
