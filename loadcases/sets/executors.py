"""Where the runs of a set are solved: in this process, a local process pool, or Dask.

Every executor has one method, `map_unordered(fn, items)`, yielding `(index, fn(item))` as
runs finish (any order); the caller puts results back in run order, so the numbers never
depend on the executor. `fn` and the items must be picklable (module-level function,
frozen data), and `fn` must not raise for one item's sake (a failing run is a result).

Dask (`dask.distributed`, optional extra `dask`): workers solve and send the solution back;
this process writes every result file, so workers need the input files (same paths, e.g.
a shared file system) but no access to the output folder.

Interrupts (`loadcases.foundation.interrupts`): after SIGINT or SIGTERM no new run starts; the runs
being solved in local workers stop and come back with their rows (status `interrupted`);
no worker outlives the pool, and a worker ends with this process however it ends (SIGKILL
too: `interrupts.worker_init`). On Dask the runs under way are cancelled.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import Future, InvalidStateError, ProcessPoolExecutor, as_completed
from concurrent.futures import TimeoutError as FuturesTimeout
from contextlib import ExitStack, contextmanager
from typing import Any, Protocol

from loadcases.foundation import interrupts

__all__ = [
    "LOCAL_SCHEDULER",
    "DaskExecutor",
    "Executor",
    "PoolExecutor",
    "SerialExecutor",
    "default_jobs",
    "make_executor",
    "scheduler_problem",
]

LOCAL_SCHEDULER = "local"  # `--scheduler local`: a Dask LocalCluster on this machine
SCHEDULER_TIMEOUT = 10.0  # s: a scheduler not reached by then is an error (exit 2)
_NO_DASK = "--scheduler needs dask.distributed: pip install 'loads[dask]'"


def default_jobs() -> int:
    """Worker processes by default: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


class Executor(Protocol):
    """Runs `fn` over items; yields `(index, result)` as each finishes."""

    def map_unordered(
        self, fn: Callable[[Any], Any], items: list[Any]
    ) -> Iterator[tuple[int, Any]]: ...


class SerialExecutor:
    """One run after another in this process."""

    def map_unordered(
        self, fn: Callable[[Any], Any], items: list[Any]
    ) -> Iterator[tuple[int, Any]]:
        for index, item in enumerate(items):
            if interrupts.received() is not None:
                return
            yield index, fn(item)


class PoolExecutor:
    """A local process pool of `jobs` workers (serial when one worker or one item)."""

    def __init__(self, jobs: int) -> None:
        if jobs < 1:
            raise ValueError(f"jobs must be at least 1, got {jobs}")
        self.jobs = jobs

    def forks(self, count: int) -> bool:
        """Whether `map_unordered` over `count` items starts worker processes that inherit
        this process's memory (forked: what it has loaded, they need not load again)."""
        return min(self.jobs, count) > 1 and multiprocessing.get_start_method() == "fork"

    def map_unordered(
        self, fn: Callable[[Any], Any], items: list[Any]
    ) -> Iterator[tuple[int, Any]]:
        workers = min(self.jobs, len(items))
        if workers <= 1:
            yield from SerialExecutor().map_unordered(fn, items)
            return
        others = {p.pid for p in multiprocessing.active_children()}
        pool = ProcessPoolExecutor(
            max_workers=workers, initializer=interrupts.worker_init, initargs=(os.getpid(),)
        )
        futures: dict[Future, int] = {}
        finished = False
        quiet = ExitStack()  # from an interrupt until the pool has shut down
        try:
            with interrupts.deferred():  # the workers start here: a signal waits till after
                for index, item in enumerate(items):
                    futures[pool.submit(interrupts.in_task, fn, item)] = index
            for future in as_completed(futures):
                yield futures[future], future.result()
            finished = True
        except KeyboardInterrupt:
            quiet.enter_context(_quiet_broken_pool())  # the workers die from here on
            yield from _interrupted_runs(pool, futures, _Workers(others))
            raise
        finally:
            with quiet, _quiet_broken_pool():
                if not finished:  # interrupt, error or the caller stopped early: no worker left
                    pool.shutdown(wait=False, cancel_futures=True)
                    for process in _Workers(others).alive():
                        process.kill()
                pool.shutdown(wait=True)


@contextmanager
def _quiet_broken_pool() -> Iterator[None]:
    """While the pool shuts down: its management thread, finding the workers killed, sets
    an exception on futures already cancelled, and CPython 3.11 prints that thread's
    InvalidStateError as a traceback (the runs are accounted for: not an error of ours)."""
    previous = threading.excepthook

    def hook(args: threading.ExceptHookArgs) -> None:
        if not isinstance(args.exc_value, InvalidStateError):
            previous(args)

    threading.excepthook = hook
    try:
        yield
    finally:
        threading.excepthook = previous


class _Workers:
    """The pool's worker processes: this process's children but the `others` (pids)."""

    def __init__(self, others: set[int | None]) -> None:
        self.others = others

    def alive(self) -> list[multiprocessing.process.BaseProcess]:
        return [p for p in multiprocessing.active_children() if p.pid not in self.others]

    def pids(self) -> list[int]:
        return [p.pid for p in self.alive() if p.pid is not None]


def _interrupted_runs(
    pool: ProcessPoolExecutor, futures: dict[Future, int], workers: _Workers
) -> Iterator[tuple[int, Any]]:
    """After an interrupt: cancel the runs not started, stop the ones under way (the signal
    forwarded to the workers) and yield those that come back within the grace time."""
    for future in futures:  # here, before waiting: a future the pool's thread cancels later
        future.cancel()  # would never wake `as_completed`, which then waits the grace time out
    pool.shutdown(wait=False, cancel_futures=True)
    interrupts.forward(interrupts.received() or signal.SIGINT, workers.pids())
    running = [f for f in futures if not f.cancelled()]
    try:
        for future in as_completed(running, timeout=interrupts.GRACE_SECONDS):
            if future.exception() is None:
                yield futures[future], future.result()
    except FuturesTimeout:
        pass


class DaskExecutor:
    """Runs on a Dask cluster: `address` of a scheduler (`tcp://host:8786`) or `"local"`
    for a `LocalCluster` of `jobs` single-threaded workers (`cluster_options` are passed
    to `LocalCluster`, e.g. `processes=False` for threads in this process)."""

    def __init__(
        self,
        address: str,
        *,
        jobs: int | None = None,
        cluster_options: dict[str, Any] | None = None,
    ) -> None:
        self.address = address
        self.jobs = jobs or default_jobs()
        self.cluster_options = dict(cluster_options or {})

    def _client(self) -> tuple[Any, Any]:
        try:
            from dask.distributed import Client, LocalCluster
        except ImportError as error:
            raise RuntimeError(_NO_DASK) from error
        if self.address != LOCAL_SCHEDULER:
            return Client(self.address, timeout=SCHEDULER_TIMEOUT), None
        options = {
            "n_workers": self.jobs,
            "threads_per_worker": 1,
            "dashboard_address": None,
        } | self.cluster_options
        cluster = LocalCluster(**options)
        return Client(cluster), cluster

    def map_unordered(
        self, fn: Callable[[Any], Any], items: list[Any]
    ) -> Iterator[tuple[int, Any]]:
        if not items:
            return
        from dask.distributed import as_completed as dask_completed

        client, cluster = self._client()
        try:
            futures = [client.submit(fn, item, pure=False) for item in items]
            index = {future.key: k for k, future in enumerate(futures)}
            for future in dask_completed(futures):
                yield index[future.key], future.result()
        finally:
            client.close()
            if cluster is not None:
                cluster.close()


def scheduler_problem(address: str, timeout: float = SCHEDULER_TIMEOUT) -> str | None:
    """Why `--scheduler address` cannot be used (None: it can): dask missing, or no
    scheduler answering there within `timeout` (s)."""
    try:
        from dask.distributed import Client
    except ImportError:
        return _NO_DASK
    if address == LOCAL_SCHEDULER:
        return None
    try:
        client = Client(address, timeout=timeout)
    except (OSError, TimeoutError, ValueError, TypeError) as error:
        reason = str(error).splitlines()[0][:120] if str(error) else type(error).__name__
        return f"cannot reach a Dask scheduler at {address!r} within {timeout:g} s ({reason})"
    client.close()
    return None


def make_executor(
    *, jobs: int | None, scheduler: str | None, cluster_options: Iterable[tuple[str, Any]] = ()
) -> Executor:
    """The executor for `--jobs` / `--scheduler` (`jobs` None: the number of cores)."""
    if scheduler:
        return DaskExecutor(scheduler, jobs=jobs, cluster_options=dict(cluster_options))
    jobs = jobs or default_jobs()
    return SerialExecutor() if jobs == 1 else PoolExecutor(jobs)
