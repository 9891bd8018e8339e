"""The coordinate equations' functions of time (a motion's f(t), Python objects) read from a
compiled run of steps: `functions_at` calls back into Python through numba's object mode
(about 6 us a call, once per attempted step), so that a run whose motions are functions of
time (a driven hub, a crank at constant speed) stays in one compiled call. A run registers
its filler with `calling` and passes the handle to the kernel; handle 0 (NO_CALL) means
the functions are constant and the array passed in already holds them.
"""

from __future__ import annotations

import itertools
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager, nullcontext
from typing import Any

import numpy as np

from mechlib.core import jit
from mechlib.core.jit import KERNEL, JitOptions, njit

__all__ = ["NO_CALL", "calling", "functions_at"]

NO_CALL = 0  # the handle of constant functions: nothing to call
Filler = Callable[[float, np.ndarray], None]  # (t (s), out (equations, 3)) -> None

# KERNEL's options but nogil: its object mode holds the GIL
CALLBACK: JitOptions = {**KERNEL, "nogil": False}
_fillers: dict[int, Filler] = {}
_handles = itertools.count(1)
_lock = threading.Lock()
objmode: Any = nullcontext  # interpreted kernels: plain Python; compiled: numba.objmode


def _bind_objmode() -> None:
    global objmode
    import numba

    objmode = numba.objmode


jit.on_compile(_bind_objmode)


def _fill(handle: int, t: float, out: np.ndarray) -> None:
    """out (equations, 3) = value, rate, acceleration of each function at t (s)."""
    _fillers[handle](t, out)


@njit(**CALLBACK)
def functions_at(handle, t, out):
    """out (equations, 3) = the coordinate equations' functions at t (s) from the filler
    registered under `handle` (`calling`); unchanged for NO_CALL (constant functions)."""
    if handle != NO_CALL:
        with objmode():
            _fill(handle, t, out)


@contextmanager
def calling(fill: Filler) -> Iterator[int]:
    """A handle for `functions_at` that calls `fill`, valid within the block."""
    with _lock:
        handle = next(_handles)
        _fillers[handle] = fill
    try:
        yield handle
    finally:
        with _lock:
            del _fillers[handle]
