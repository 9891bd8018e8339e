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
within `GRACE_SECONDS`. The parent starts its workers within `deferred()`: a signal that
reaches the parent or a new worker before the worker's `worker_init` is recorded, never
raised there (no traceback from a worker's start-up), and the parent raises it once its
workers are started. A worker ends with its parent, however the parent ends (SIGKILL too):
on Linux the kernel kills it (`PR_SET_PDEATHSIG`), elsewhere (and as a second line on Linux)
a thread of the worker sees its parent change within `WATCH_SECONDS` and ends the process.
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager, suppress
from typing import Any

__all__ = [
    "GRACE_SECONDS",
    "REDELIVER_SECONDS",
    "WATCH_SECONDS",
    "Interrupted",
    "deferred",
    "exit_code",
    "forward",
    "in_task",
    "on_signals",
    "received",
    "signal_name",
    "worker_init",
    "wrap_up",
]

GRACE_SECONDS = 20.0  # a worker's time to return its interrupted run before it is killed
WATCH_SECONDS = 0.5  # how often a worker checks that its parent is alive
REDELIVER_SECONDS = 0.001  # an interrupt lost in a finaliser is sent again this much later
_PR_SET_PDEATHSIG = 1  # prctl(2): the signal this process gets when its parent dies
_SIGNALS = (signal.SIGINT, signal.SIGTERM)
_received: int | None = None
_in_task = False  # worker processes: a run is being solved


class Interrupted(KeyboardInterrupt):
    """A signal stopped the work: `signum` is SIGINT or SIGTERM."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal_name(signum))
        self.signum = signum

    def __reduce__(self) -> tuple[type[Interrupted], tuple[int]]:
        # a worker sends its run's interrupt back to the parent pickled: rebuilt from the
        # number (from its args, the name, it could not be rebuilt and the pool would break)
        return (Interrupted, (int(self.signum),))


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
def _handling(handler: Callable[[int, Any], None]) -> Iterator[dict]:
    """Within: `handler` for SIGINT and SIGTERM; yields the handlers before, put back after."""
    before = {s: signal.getsignal(s) for s in _SIGNALS}
    for s in _SIGNALS:
        signal.signal(s, handler)
    try:
        yield before
    finally:
        for s, previous in before.items():
            signal.signal(s, previous)


@contextmanager
def on_signals() -> Iterator[None]:
    """Within: SIGINT and SIGTERM raise `Interrupted` (main thread only; elsewhere a no-op)."""
    global _received
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _received = None
    with _handling(_raise), _redelivering(_raise):
        yield


@contextmanager
def _redelivering(handler: Callable[[int, Any], None]) -> Iterator[None]:
    """Within: an `Interrupted` raised where Python cannot propagate it (a weakref callback
    or `__del__` that the signal's handler happened to run in: CPython prints it as
    "Exception ignored in ..." with a traceback and goes on) is delivered again, by the
    same signal to this process with `handler` installed: it then raises at the next
    instruction, in the code that was running."""
    previous = sys.unraisablehook
    sys.unraisablehook = _redeliver_hook(handler, previous)
    try:
        yield
    finally:
        sys.unraisablehook = previous


def _redeliver_hook(handler: Callable[[int, Any], None], previous: Any) -> Any:
    def hook(args: Any) -> None:
        if not isinstance(args.exc_value, Interrupted):
            previous(args)
            return
        signum = args.exc_value.signum
        later: threading.Timer | None = None
        while True:  # a further signal may raise in here too: then armed again, once
            try:
                if later is not None:
                    later.cancel()
                for s in _SIGNALS:
                    signal.signal(s, handler)
                # sent again from a thread a moment later: its handler then runs in the code
                # that was running (sent or marked from here, it would run inside this hook,
                # where it is ignored again)
                later = threading.Timer(REDELIVER_SECONDS, os.kill, (os.getpid(), signum))
                later.daemon = True
                later.start()
                return
            except Interrupted as again:
                signum = again.signum

    return hook


def _record(signum: int, _frame: Any) -> None:
    global _received
    _received = _received or signum


@contextmanager
def deferred() -> Iterator[None]:
    """Within: SIGINT and SIGTERM are only recorded (main thread only; elsewhere a no-op).

    Processes forked within inherit that, so a signal that reaches a new worker before its
    `worker_init` is recorded there (the worker then starts no run) instead of raised in its
    start-up. On leaving, a signal recorded within is raised as `Interrupted` if the
    handlers outside raise (`on_signals`)."""
    with _recording(_record):
        yield


@contextmanager
def wrap_up() -> Iterator[None]:
    """Within: the first SIGINT or SIGTERM is recorded and the work goes on (a finished
    run's files are written whole), a second one raises `Interrupted`, as one received
    before does (main thread only; elsewhere a no-op). On leaving, a signal recorded
    within is raised as `Interrupted` if the handlers outside raise (`on_signals`)."""
    with _recording(_second_raises):
        yield


def _second_raises(signum: int, _frame: Any) -> None:
    global _received
    if _received is not None:
        raise Interrupted(signum)
    _received = signum


@contextmanager
def _recording(handler: Callable[[int, Any], None]) -> Iterator[None]:
    """Within: `handler` for SIGINT and SIGTERM (main thread only); on leaving, a signal
    received within raised as `Interrupted` where the handlers outside raise."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    earlier = _received
    with _handling(handler) as before:
        yield
    if earlier is None and _received is not None and before[signal.Signals(_received)] is _raise:
        raise Interrupted(_received)


def _worker_signal(signum: int, _frame: Any) -> None:
    global _received
    _received = _received or signum
    if _in_task:
        # one stop per run: the wrap-up (requests, pickling) goes on. Recorded, not
        # SIG_IGN: a signal already pending (the pool's SIGTERM to a worker it finds
        # broken) would meet SIG_IGN as CPython's "Signal 15 ignored due to race
        # condition" OSError, raised anywhere in the worker and printed as a traceback
        for s in _SIGNALS:
            signal.signal(s, _record)
        raise Interrupted(signum)


def worker_init(parent: int | None = None) -> None:
    """Initializer of pool workers: a signal stops the run under way, none is ignored; with
    `parent` (the pid of the process making the pool) the worker ends when that one does."""
    for s in _SIGNALS:
        signal.signal(s, _worker_signal)
    # a run's interrupt that lands in a callback is raised again (`_redelivering`); for the
    # worker's life, which ends with os._exit
    sys.unraisablehook = _redeliver_hook(_worker_signal, sys.unraisablehook)
    if parent is not None:
        _end_with(parent)


def _end_with(parent: int) -> None:
    """End this process (`os._exit`) as soon as `parent` is no longer its parent."""
    if sys.platform.startswith("linux"):
        with suppress(OSError, AttributeError):
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
    if os.getppid() != parent:  # the parent died before it could be watched
        os._exit(exit_code(signal.SIGKILL))
    watcher = threading.Thread(target=_watch, args=(parent,), name="loads-parent", daemon=True)
    watcher.start()


def _watch(parent: int) -> None:
    while os.getppid() == parent:
        time.sleep(WATCH_SECONDS)
    os._exit(exit_code(signal.SIGKILL))


def in_task(fn: Callable[[Any], Any], item: Any) -> Any:
    """`fn(item)` in a pool worker, interruptible by a signal while it runs."""
    global _in_task
    _in_task = True  # first: a signal from here on raises, one before is in `_received`
    try:
        if _received is not None:  # interrupted before this run began: do not start it
            raise Interrupted(_received)
        return fn(item)
    finally:
        _in_task = False


def forward(signum: int, pids: Iterable[int]) -> None:
    """Send `signum` to each process in `pids` that still exists."""
    for pid in pids:
        with suppress(ProcessLookupError, PermissionError):
            os.kill(pid, signum)
