"""Settings of a process that solves runs: one BLAS thread, a frozen heap.

A run's matrices are small (saddle matrices of tens to hundreds of rows, factored one at a
time), where OpenBLAS's threads cost more in hand-over than they gain, and `loads run -j N`
already puts one process on each core. With two BLAS threads per process on a busy 2-core
machine, each small product spins for a time slice: the 10-loop four-bar chain's toggle
check took 66 ms per recorded row instead of 0.5 ms (2026-11-28). threadpoolctl (the
scikit-learn project's library) sets the limit of the BLAS already loaded, which an
environment variable set after numpy's import cannot; the environment variables, set too,
limit the BLAS loaded afterwards (scipy's own OpenBLAS is a second library, loaded with
scipy.linalg: left at its default it ran the door set's workers with two spinning threads
each, five times slower, 2026-11-28) and the processes started from this one. A user who
sets OPENBLAS_NUM_THREADS, OMP_NUM_THREADS or MKL_NUM_THREADS keeps their own setting.

After its first run a process's heap holds about 150,000 long-lived objects (numba, scipy,
pandas); each full collection of the cyclic garbage collector walks them all, about 70 ms,
which happened in one run of five of the slider-crank (0.17 s). `gc.freeze()` moves them
out of the collector's sight; what later runs leave behind is still collected.
"""

from __future__ import annotations

import gc
import os

__all__ = ["freeze_heap", "one_blas_thread"]

_USER_SETTINGS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
_limited = False
_frozen = False


def one_blas_thread() -> bool:
    """Limit this process's BLAS to one thread, once (True when the limit was set now or
    before; False when the user's environment sets the threads)."""
    global _limited
    if _limited:
        return True
    if any(os.environ.get(name) for name in _USER_SETTINGS):
        return False
    for name in _USER_SETTINGS:  # read by each BLAS library as it loads
        os.environ[name] = "1"
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=1, user_api="blas")  # the ones loaded already
    _limited = True
    return True


def freeze_heap() -> None:
    """Move every object alive now into the collector's permanent generation, once per
    process (after its first run: modules and compiled kernels loaded)."""
    global _frozen
    if not _frozen:
        gc.freeze()
        _frozen = True
