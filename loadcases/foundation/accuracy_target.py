"""The accuracy target's rule, one for a case's `analysis.accuracy` and `loads accuracy
--target`: its default and the bounds it lies between, both fractions of each request's
peak (dimensionless)."""

from __future__ import annotations

__all__ = [
    "DEFAULT_ACCURACY",
    "TARGET_ABOVE",
    "TARGET_BELOW",
    "target_problem",
]

DEFAULT_ACCURACY = 1e-3  # of each request's peak: the sizing accuracy
# the target lies strictly between these: an error of 0 cannot be met, one of the whole
# peak says nothing
TARGET_ABOVE = 0.0
TARGET_BELOW = 1.0


def target_problem(target: float) -> str | None:
    """Why `target` (a fraction of each request's peak) is no accuracy target, or None."""
    if TARGET_ABOVE < target < TARGET_BELOW:
        return None
    return (
        f"{target:g} must lie between {TARGET_ABOVE:g} and {TARGET_BELOW:g} "
        "(a fraction of the peak)"
    )
