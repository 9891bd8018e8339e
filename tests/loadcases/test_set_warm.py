"""The kernels a set's runs use are loaded in the parent before its pool forks
(loadcases.sets.warm): the short copy loads every kernel the whole run calls, and no run
starts after an interrupt met while warming."""

from __future__ import annotations

import multiprocessing
from pathlib import Path

import pytest

from benchmarks.campaign import write_sweep
from loadcases.foundation import interrupts
from loadcases.inputs.loader import load_case
from loadcases.sets import campaign, warm
from loadcases.sets.executors import PoolExecutor
from loadcases.sets.specs import load_and_compile_set
from mechlib.core import jit
from tests.loadcases.set_fixtures import CRANK_CASE, CRANK_MECH


def _loaded() -> set[tuple[str, int]]:
    """(kernel, signatures loaded) of every mechlib kernel compiled or read from the cache."""
    return {
        (f"{k.py_func.__module__}.{k.__name__}", len(getattr(k.dispatcher, "signatures", ())))
        for k in jit._marked
        if getattr(k.dispatcher, "signatures", None)
    }


def test_the_short_copy_of_the_campaign_run_loads_every_kernel_the_whole_run_calls(
    tmp_path: Path,
) -> None:
    set_file = write_sweep(tmp_path, [3.0, 9.0])
    specs = list(load_and_compile_set(set_file).runs)
    short = warm.short_copy(load_case(specs[0].case_path))
    assert short is not None and short.case.analysis.end == pytest.approx(2e-3)  # 2 x 1 ms
    assert warm.warm_kernels(specs)
    assert jit.compiled()
    before = _loaded()
    assert len(before) >= 20  # the campaign's run calls 26 (2026-11-29)
    outcome = campaign.solve_spec(specs[1])  # the whole run, 1 s: nothing more to load
    assert outcome.solution.status == "ok"
    assert _loaded() == before


def test_analyses_not_cut_by_their_end_are_not_warmed(tmp_path: Path) -> None:
    (tmp_path / "crank.mech.yaml").write_text(CRANK_MECH)
    case = tmp_path / "crank.case.yaml"
    case.write_text(CRANK_CASE)
    kinematic = warm.short_copy(load_case(case))
    assert kinematic is not None and kinematic.case.analysis.end == pytest.approx(0.1)
    case.write_text(CRANK_CASE.replace("{type: kinematic, end: 0.5, step: 0.05}", "{type: static}"))
    assert warm.short_copy(load_case(case)) is None


def test_an_interrupt_while_warming_starts_no_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "crank.mech.yaml").write_text(CRANK_MECH)
    (tmp_path / "crank.case.yaml").write_text(CRANK_CASE)
    (tmp_path / "crank.set.yaml").write_text(
        "set: crank\ncases: [crank.case.yaml]\nsweep: {speed: [1.0, 2.0]}\n"
    )
    started: list[object] = []

    def solve(spec: object) -> None:
        started.append(spec)

    monkeypatch.setattr(campaign, "solve_spec", solve)  # a run started fails the test
    monkeypatch.setattr(interrupts, "received", lambda: 2)  # SIGINT met while warming
    result = campaign.run_set(
        tmp_path / "crank.set.yaml", output_dir=tmp_path / "out", executor=PoolExecutor(2)
    )
    assert result.interrupted and result.records == [] and started == []
    assert not (tmp_path / "out" / "crank" / "envelope.csv").exists()


def test_a_pool_forks_only_for_more_than_one_worker() -> None:
    fork = multiprocessing.get_start_method() == "fork"
    assert not PoolExecutor(2).forks(1) and not PoolExecutor(1).forks(5)
    assert PoolExecutor(2).forks(2) == fork


def test_the_collector_is_paused_within_the_block_and_as_it_was_after() -> None:
    import gc

    from loadcases.sets.collector import collector_paused

    was_on = gc.isenabled()
    try:
        for state in (True, False):
            (gc.enable if state else gc.disable)()
            with collector_paused():
                assert not gc.isenabled()
            assert gc.isenabled() is state
        gc.enable()
        with pytest.raises(RuntimeError), collector_paused():
            raise RuntimeError("a failing step")
        assert gc.isenabled()
    finally:
        (gc.enable if was_on else gc.disable)()


def test_a_warm_run_that_cannot_be_solved_costs_its_time_only(tmp_path: Path) -> None:
    from loadcases.sets.specs import RunSpec

    missing = RunSpec("gone", "gone", str(tmp_path / "gone.case.yaml"), (), (), "0" * 64)
    assert warm.warm_kernels([missing, missing])  # no error: the real run reports it
