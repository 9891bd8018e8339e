"""The cyclic garbage collector paused while a set's parent builds what lives long.

Loading compiled kernels (`loadcases.sets.warm`) and building the workbook (tens of
thousands of cells) create many objects that stay alive and few that die in cycles; each
collection in between walks the young ones again and frees nothing. Paused there, the
campaign's parent (`loads run SET -j 2`, 200 runs) spent 0.13 s of CPU less of its 2.6 s,
0.07 s in each (2026-11-29, two runs each way; importing matplotlib and openpyxl gained
nothing: not paused). What those steps leave in cycles is
collected once the collector runs again.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["collector_paused"]


@contextmanager
def collector_paused() -> Iterator[None]:
    """The collector off within the block, as it was after (left off if it was off)."""
    was_on = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_on:
            gc.enable()
