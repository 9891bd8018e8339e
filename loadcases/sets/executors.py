"""Where the runs of a set are solved: in this process, a local process pool, or Dask.

Every executor has one method, `map_unordered(fn, items)`, yielding `(index, fn(item))` as
runs finish (any order); the caller puts results back in run order, so the numbers never
depend on the executor. `fn` and the items must be picklable (module-level function,
frozen data), and `fn` must not raise for one item's sake (a failing run is a result).

Dask (`dask.distributed`, optional extra `dask`): workers solve and send the solution back;
this process writes every result file, so workers need the input files (same paths, e.g.
a shared file system) but no access to the output folder.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Any, Protocol

__all__ = [
    "LOCAL_SCHEDULER",
    "DaskExecutor",
    "Executor",
    "PoolExecutor",
    "SerialExecutor",
    "default_jobs",
    "make_executor",
]

LOCAL_SCHEDULER = "local"  # `--scheduler local`: a Dask LocalCluster on this machine


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
            yield index, fn(item)


class PoolExecutor:
    """A local process pool of `jobs` workers (serial when one worker or one item)."""

    def __init__(self, jobs: int) -> None:
        if jobs < 1:
            raise ValueError(f"jobs must be at least 1, got {jobs}")
        self.jobs = jobs

    def map_unordered(
        self, fn: Callable[[Any], Any], items: list[Any]
    ) -> Iterator[tuple[int, Any]]:
        workers = min(self.jobs, len(items))
        if workers <= 1:
            yield from SerialExecutor().map_unordered(fn, items)
            return
        with ProcessPoolExecutor(max_workers=workers) as pool:
            futures = {pool.submit(fn, item): index for index, item in enumerate(items)}
            for future in as_completed(futures):
                yield futures[future], future.result()


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
            raise RuntimeError(
                "--scheduler needs dask.distributed: pip install 'loads[dask]'"
            ) from error
        if self.address != LOCAL_SCHEDULER:
            return Client(self.address), None
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


def make_executor(
    *, jobs: int | None, scheduler: str | None, cluster_options: Iterable[tuple[str, Any]] = ()
) -> Executor:
    """The executor for `--jobs` / `--scheduler` (`jobs` None: the number of cores)."""
    if scheduler:
        return DaskExecutor(scheduler, jobs=jobs, cluster_options=dict(cluster_options))
    jobs = jobs or default_jobs()
    return SerialExecutor() if jobs == 1 else PoolExecutor(jobs)
