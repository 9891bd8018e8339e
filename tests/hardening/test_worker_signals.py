"""Issue 39 item 4: signals at any instant.

No pool worker outlives `loads`, however it ends (SIGKILL too: a worker would otherwise go
on solving and hold the caller's stdout open), and SIGINT or SIGTERM at start-up or while
the workers start gives the promised message and exit status promptly, with no traceback
from any process.
"""

from __future__ import annotations

import os
import signal
import sys
import time
from pathlib import Path

import pytest

from loadcases.foundation.interrupts import exit_code
from tests.hardening.test_interrupts import _children, _start, _wait_for, _write

PROMPTLY = 10.0  # s: generous for a loaded machine; the work itself takes well under 5 s


def _two_slow_runs(folder: Path) -> None:
    """`two.set.yaml`: two runs of minutes each, one per worker with `-j 2`."""
    _write(folder)
    (folder / "two.set.yaml").write_text(
        "set: two\ncases: [slow-a.case.yaml]\nsweep: {swing: [0.5, 1.0]}\n"
    )


def _alive(pid: int) -> bool:
    """The process exists and is not a zombie (an orphan's new parent may not reap it)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except (FileNotFoundError, ProcessLookupError):
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def _ended(pids: list[int], timeout: float = PROMPTLY) -> bool:
    deadline = time.monotonic() + timeout
    while any(_alive(p) for p in pids) and time.monotonic() < deadline:
        time.sleep(0.05)
    return not any(_alive(p) for p in pids)


def _kill(pids: list[int]) -> None:
    """Leave no process behind, whatever the test found."""
    for pid in pids:
        if _alive(pid):
            os.kill(pid, signal.SIGKILL)


def _catches(pid: int, signum: int) -> bool:
    """The process has a handler of `signum` (its SigCgt mask in /proc)."""
    try:
        lines = Path(f"/proc/{pid}/status").read_text().splitlines()
    except (FileNotFoundError, ProcessLookupError):
        return False
    mask = next(int(line.split()[1], 16) for line in lines if line.startswith("SigCgt:"))
    return bool(mask >> (signum - 1) & 1)


def test_sigkill_of_loads_ends_its_workers(tmp_path: Path) -> None:
    _two_slow_runs(tmp_path)
    process = _start(tmp_path, "run", "two.set.yaml", "-j", "2", "-o", "out")
    workers: list[int] = []
    try:
        _wait_for(lambda: len(_children(process.pid)) == 2, process)
        workers = _children(process.pid)
        process.kill()
        process.wait(timeout=PROMPTLY)
        assert _ended(workers), "a worker outlived loads killed by SIGKILL"
        # nothing holds the caller's pipes open: they reach EOF
        _, stderr = process.communicate(timeout=PROMPTLY)
        assert "Traceback" not in stderr
    finally:
        _kill([process.pid, *workers])


@pytest.mark.parametrize(
    ("signum", "moment"),
    [
        (signal.SIGTERM, "start-up"),
        (signal.SIGTERM, "workers starting"),
        (signal.SIGINT, "workers starting"),
    ],
)
def test_signal_at_start_up_or_while_workers_start_exits_promptly(
    tmp_path: Path, signum: int, moment: str
) -> None:
    _two_slow_runs(tmp_path)
    process = _start(tmp_path, "run", "two.set.yaml", "-j", "2", "-o", "out")
    seen: set[int] = set()
    try:
        if moment == "start-up":  # as soon as loads has its handler
            _wait_for(lambda: _catches(process.pid, signum), process, timeout=60.0)
        else:  # as soon as the first worker exists: before or while it starts
            _wait_for(lambda: bool(seen.update(_children(process.pid)) or seen), process)
        if signum == signal.SIGINT:
            os.killpg(process.pid, signum)  # as Ctrl-C in a terminal: workers too
        else:
            process.send_signal(signum)
        sent = time.monotonic()
        stdout, stderr = process.communicate(timeout=60)
        took = time.monotonic() - sent
        assert process.returncode == exit_code(signum), stderr
        assert f"loads: interrupted by {signal.Signals(signum).name}" in stderr
        assert "Traceback" not in stderr and "Traceback" not in stdout, stderr + stdout
        assert took < PROMPTLY, f"exit {took:.1f} s after the signal"
        assert _ended(list(seen)), "a worker outlived loads"
    finally:
        _kill([process.pid, *seen])


def test_a_broken_pools_cancelled_future_prints_no_traceback() -> None:
    """While a pool shuts down after its workers were killed, CPython 3.11's management
    thread may set an exception on a future already cancelled; the InvalidStateError it
    raises is silenced (no 'Thread-1: Traceback' on stderr), any other thread error still
    reaches the hook that was in place, which is restored afterwards."""
    import threading
    from concurrent.futures import Future

    from loadcases.sets.executors import _quiet_broken_pool

    def cancelled_then_failed() -> None:
        future: Future = Future()
        future.cancel()
        future.set_exception(RuntimeError("pool broken"))

    def other_error() -> None:
        raise ValueError("a real error")

    seen: list[str] = []
    before = threading.excepthook
    threading.excepthook = lambda args: seen.append(type(args.exc_value).__name__)
    recorder = threading.excepthook
    try:
        with _quiet_broken_pool():
            for target in (cancelled_then_failed, other_error):
                thread = threading.Thread(target=target)
                thread.start()
                thread.join()
        assert threading.excepthook is recorder
    finally:
        threading.excepthook = before
    assert seen == ["ValueError"]


def test_an_interrupt_that_lands_in_a_finaliser_is_raised_again(capsys) -> None:
    """A signal whose handler runs inside `__del__` (or a weakref callback: seen in a
    worker's import, CI 2026-11-29) raises where CPython cannot propagate it: it printed
    "Exception ignored in ..." with a traceback and the work went on. Within `on_signals`
    the interrupt is delivered again and raised in the code that was running."""
    from loadcases.foundation import interrupts

    class Dropped:
        def __del__(self) -> None:
            os.kill(os.getpid(), signal.SIGINT)
            for _ in range(10_000):  # the handler runs here, inside the finaliser
                pass

    raised = False
    try:
        with interrupts.on_signals():
            Dropped()  # finalised at once
            deadline = time.monotonic() + PROMPTLY
            while time.monotonic() < deadline:  # the work going on
                pass
    except interrupts.Interrupted as stop:
        raised = stop.signum == signal.SIGINT
    assert raised
    assert interrupts.received() == signal.SIGINT
    assert "Exception ignored" not in capsys.readouterr().err


def _interrupted_before_it_began(_item: object) -> None:
    """A pool task as `interrupts.in_task` ends when the worker's signal came before it."""
    from loadcases.foundation import interrupts

    raise interrupts.Interrupted(signal.SIGINT)


def test_a_workers_interrupt_reaches_the_parent_as_an_interrupt() -> None:
    """CI 2026-11-30: Ctrl-C while the workers started. A worker whose signal came before
    its run began sends `Interrupted` back; it was pickled by its name and could not be
    rebuilt, so the pool broke ('internal error: BrokenProcessPool', exit 1, not 130)."""
    import pickle
    from concurrent.futures import ProcessPoolExecutor

    from loadcases.foundation import interrupts

    again = pickle.loads(pickle.dumps(interrupts.Interrupted(signal.SIGTERM)))
    assert isinstance(again, interrupts.Interrupted) and again.signum == signal.SIGTERM
    with ProcessPoolExecutor(max_workers=1) as pool:
        future = pool.submit(_interrupted_before_it_began, None)
        with pytest.raises(interrupts.Interrupted) as stop:
            future.result(timeout=60)
    assert stop.value.signum == signal.SIGINT


def test_a_second_signal_while_an_interrupt_is_sent_again_is_not_lost(monkeypatch) -> None:
    """A further signal that lands while the hook arms the interrupt's redelivery (seen in
    a worker: killpg's SIGINT and the parent's forwarded one) raised inside the hook:
    'Exception ignored in sys.unraisablehook' and a traceback. It is armed again instead,
    and raised once in the code that was running."""
    import threading
    from types import SimpleNamespace

    from loadcases.foundation import interrupts

    started: list[threading.Timer] = []

    class SignalledWhileStarting(threading.Timer):
        def start(self) -> None:
            super().start()
            started.append(self)
            if len(started) == 1:
                os.kill(os.getpid(), signal.SIGTERM)  # its handler runs here, in the hook
                for _ in range(10_000):
                    pass

    monkeypatch.setattr(threading, "Timer", SignalledWhileStarting)
    armed = False
    caught: list[int] = []
    try:
        with interrupts.on_signals():
            sys.unraisablehook(SimpleNamespace(exc_value=interrupts.Interrupted(signal.SIGINT)))
            armed = True
            deadline = time.monotonic() + PROMPTLY
            while time.monotonic() < deadline:  # the work going on
                pass
    except interrupts.Interrupted as stop:
        caught.append(stop.signum)
    assert armed, "the second signal escaped the hook"
    assert caught == [signal.SIGTERM]  # the last signal, raised in the running code
    assert len(started) == 2


HANDLED = 0.2  # s of Python work in which a signal sent to this process is handled


def _busy(seconds: float) -> None:
    """Python work for `seconds` (where a signal's handler runs)."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        pass


def test_a_finished_runs_files_are_written_through_a_first_signal() -> None:
    """A first signal while a finished run's files are written (`interrupts.wrap_up`) is
    recorded and the writing goes on; it is raised after it. A late SIGTERM to `loads run`
    on a 200 001-row run lost its files there before."""
    from loadcases.foundation import interrupts

    written = False
    try:
        with interrupts.on_signals(), interrupts.wrap_up():
            os.kill(os.getpid(), signal.SIGTERM)
            _busy(HANDLED)
            written = True
    except interrupts.Interrupted as stop:
        assert stop.signum == signal.SIGTERM
    assert written and interrupts.received() == signal.SIGTERM


def test_a_second_signal_stops_the_wrap_up() -> None:
    from loadcases.foundation import interrupts

    reached = []
    with pytest.raises(interrupts.Interrupted), interrupts.on_signals(), interrupts.wrap_up():
        os.kill(os.getpid(), signal.SIGTERM)
        _busy(HANDLED)
        reached.append("first recorded")
        os.kill(os.getpid(), signal.SIGINT)
        _busy(HANDLED)
        reached.append("second not raised")
    assert reached == ["first recorded"]
