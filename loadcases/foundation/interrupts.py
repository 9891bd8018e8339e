"""SIGINT and SIGTERM: stop the run under way cleanly and say so.

`loads run` installs `on_signals()` in its main process. The first SIGINT or SIGTERM is
recorded (`received()`) and raised as `Interrupted` (a KeyboardInterrupt) where Python is
running: inside a solve, mechlib turns it into a run with status `interrupted` and the rows
computed so far; a set then starts no new run and writes no envelope; the command exits
128 + the signal number (130 for SIGINT, 143 for SIGTERM). A second signal interrupts the
wrap-up too.

Worker processes of a pool run `worker_init()`: a signal stops the run a worker is solving
in the same way (its rows come back as an interrupted run) and is ignored between runs; the
parent forwards its signal to its workers (`forward`) and ends the ones that do not return
within `GRACE_SECONDS`.
"""

from __future__ import annotations

import os
import signal
import threading
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager, suppress
from typing import Any

__all__ = [
    "GRACE_SECONDS",
    "Interrupted",
    "exit_code",
    "forward",
    "in_task",
    "on_signals",
    "received",
    "signal_name",
    "worker_init",
]

GRACE_SECONDS = 20.0  # a worker's time to return its interrupted run before it is killed
_SIGNALS = (signal.SIGINT, signal.SIGTERM)
_received: int | None = None
_in_task = False  # worker processes: a run is being solved


class Interrupted(KeyboardInterrupt):
    """A signal stopped the work: `signum` is SIGINT or SIGTERM."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal_name(signum))
        self.signum = signum


def received() -> int | None:
    """The first signal this process received (None: not interrupted)."""
    return _received


def signal_name(signum: int) -> str:
    """`SIGINT`, `SIGTERM`."""
    return signal.Signals(signum).name


def exit_code(signum: int) -> int:
    """The shell's exit status of a command stopped by `signum` (130 SIGINT, 143 SIGTERM)."""
    return 128 + int(signum)


def _raise(signum: int, _frame: Any) -> None:
    global _received
    _received = _received or signum
    raise Interrupted(signum)


@contextmanager
def on_signals() -> Iterator[None]:
    """Within: SIGINT and SIGTERM raise `Interrupted` (main thread only; elsewhere a no-op)."""
    global _received
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = {s: signal.getsignal(s) for s in _SIGNALS}
    _received = None
    for s in _SIGNALS:
        signal.signal(s, _raise)
    try:
        yield
    finally:
        for s, handler in before.items():
            signal.signal(s, handler)


def _worker_signal(signum: int, _frame: Any) -> None:
    global _received
    _received = _received or signum
    if _in_task:
        for s in _SIGNALS:  # one stop per run: the wrap-up (requests, pickling) goes on
            signal.signal(s, signal.SIG_IGN)
        raise Interrupted(signum)


def worker_init() -> None:
    """Initializer of pool workers: a signal stops the run under way, none is ignored."""
    for s in _SIGNALS:
        signal.signal(s, _worker_signal)


def in_task(fn: Callable[[Any], Any], item: Any) -> Any:
    """`fn(item)` in a pool worker, interruptible by a signal while it runs."""
    global _in_task
    if _received is not None:  # interrupted before this run began: do not start it
        raise Interrupted(_received)
    _in_task = True
    try:
        return fn(item)
    finally:
        _in_task = False


def forward(signum: int, pids: Iterable[int]) -> None:
    """Send `signum` to each process in `pids` that still exists."""
    for pid in pids:
        with suppress(ProcessLookupError, PermissionError):
            os.kill(pid, signum)
