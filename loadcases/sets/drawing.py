"""The process that draws a large set's envelope plots, forked before the kernels' warm-up.

A set's parent loads the compiled kernels alone before it forks its solving workers
(`loadcases.sets.warm`): one core idles meanwhile. A set of many runs has its envelope plots
drawn by a process beside the workbook (`loadcases.sets.campaign._plots`), which needs
matplotlib (0.24 s of CPU to import). Forked just before the warm-up, that process imports
matplotlib on the idle core and then waits, idle, for the plots; the parent no longer
imports matplotlib while the workers solve (where its CPU is taken from them) and forks no
process after the last run. Like the solving workers it ends with the parent however that
ends, and a signal reaching it between tasks is only recorded
(`loadcases.foundation.interrupts.worker_init`).
"""

from __future__ import annotations

import importlib
import os
from concurrent.futures import ProcessPoolExecutor

from loadcases.foundation import interrupts

__all__ = ["PLOT_MODULE", "Drawing"]

PLOT_MODULE = "loadcases.report.plots"  # the envelope plots' module (imports matplotlib)


class Drawing:
    """The plots' process of a set, once `start` has forked it (`pool`: None before)."""

    def __init__(self) -> None:
        self.pool: ProcessPoolExecutor | None = None

    def start(self) -> None:
        """Fork the process (it imports matplotlib at once); call before the warm-up."""
        with interrupts.deferred():  # a signal waits till the process has its handlers
            self.pool = ProcessPoolExecutor(
                max_workers=1, initializer=_prepare, initargs=(os.getpid(),)
            )
            self.pool.submit(int)  # the pool forks at its first task

    def close(self) -> None:
        """End the process (after its plots, if any are being drawn)."""
        if self.pool is not None:
            self.pool.shutdown(wait=True, cancel_futures=True)
            self.pool = None


def _prepare(parent: int) -> None:
    """The process's start: the workers' signal handling, then matplotlib imported."""
    interrupts.worker_init(parent)
    importlib.import_module(PLOT_MODULE)
