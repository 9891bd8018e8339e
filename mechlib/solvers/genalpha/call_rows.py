"""How many output rows one compiled whole-run call takes (mechlib.solvers.genalpha.run and
.modal_run).

Between calls the progress bar moves and a signal is served (a compiled call cannot be
interrupted), and each call costs its Python around the kernel: the state packed and
unpacked, the rows recorded (0.25-0.33 ms a call on the campaign's slider-crank, whose
1001 rows took four calls of 256). The first call takes FIRST_ROWS; each next one as many
rows as the last call's pace fits in CALL_SECONDS of wall time, never fewer than
FIRST_ROWS, nor more than MOST_ROWS or MOST_CELLS values of recorded state; a run whose
steps a companion follows beside it (mechlib.model.step_feed) FED_ROWS and FED_SECONDS, so
that its steps are handed on as they come (each call costs the run its Python around it).
The rows and steps do not depend on where the calls end (tests/mechlib/test_call_rows.py), so this
pace, which the machine's load sways, changes nothing a run computes.
"""

from __future__ import annotations

import time

__all__ = [
    "CALL_SECONDS",
    "FED_ROWS",
    "FED_SECONDS",
    "FIRST_ROWS",
    "MOST_CELLS",
    "MOST_ROWS",
    "CallRows",
]

FIRST_ROWS = 256  # rows of the first call, and the fewest of any
CALL_SECONDS = 0.1  # s of wall time a call is sized to, from the last call's pace
# a run a companion follows beside it (mechlib.model.step_feed): its steps handed on sooner
FED_ROWS, FED_SECONDS = 32, 0.01
MOST_ROWS = 16384
MOST_CELLS = 1 << 20  # recorded values a call's row buffer holds at most (8 MB)


class CallRows:
    """The rows of each next call of one run, from the pace of the last: `rows(width)`
    before a call (width: values a row records), `done(written)` after it."""

    def __init__(self, first: int = FIRST_ROWS, seconds: float = CALL_SECONDS) -> None:
        self._first, self._seconds = first, seconds
        self._next = first
        self._started = 0.0

    def relax(self) -> None:
        """The calls from now on sized as by default (FIRST_ROWS, CALL_SECONDS)."""
        self._first, self._seconds = FIRST_ROWS, CALL_SECONDS

    def rows(self, width: int) -> int:
        """Rows the next call takes (recording `width` values a row); starts its clock."""
        self._started = time.perf_counter()
        return max(1, min(self._next, MOST_ROWS, MOST_CELLS // max(width, 1)))

    def done(self, written: int) -> None:
        """The call just made wrote `written` rows: the next sized to its pace."""
        took = time.perf_counter() - self._started
        if written <= 0:
            return
        fits = MOST_ROWS if took <= 0.0 else int(written * self._seconds / took)
        self._next = max(self._first, min(MOST_ROWS, fits))
