"""Work counted where it happens: factorisations and Jacobian evaluations of one solve.

`solve` opens `tally(stats)` around an analysis; `count(...)` adds to the stats of the
solve running in this thread (context variable), and does nothing outside one (a check or
an inspection), so that the linear algebra does not need the stats passed down.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

__all__ = ["count", "tally"]

_current: ContextVar = ContextVar("mechlib_work", default=None)


@contextmanager
def tally(stats) -> Iterator[None]:
    """Count the work done inside into `stats` (a SolverStats)."""
    token = _current.set(stats)
    try:
        yield
    finally:
        _current.reset(token)


def count(*, factorizations: int = 0, jacobian_evaluations: int = 0) -> None:
    """Add to the counters of the solve under way (if any)."""
    stats = _current.get()
    if stats is not None:
        stats.factorizations += factorizations
        stats.jacobian_evaluations += jacobian_evaluations
