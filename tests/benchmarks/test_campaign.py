"""The campaign benchmark's sweep, solved as a set on a pool and run by run as single cases.

No test here measures time. The sweep is the bench slider-crank (benchmarks/campaign.py),
cut to 0.2 s with 10 ms outputs so that its runs take a few seconds.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from benchmarks.campaign import PARAMETER, sweep_rates, write_sweep
from loadcases.build.model import build_run
from loadcases.inputs.loader import load_case
from loadcases.inputs.overrides import Override
from loadcases.results.files import write_results
from loadcases.run import run_file
from loadcases.run.companion import coarser
from loadcases.sets.campaign import solve_spec
from loadcases.sets.executors import Executor, PoolExecutor, SerialExecutor
from loadcases.sets.specs import load_and_compile_set

RUNS = 3


@pytest.fixture(scope="module")
def sweep(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("campaign")
    set_file = write_sweep(folder, sweep_rates(RUNS))
    case = folder / "crank.case.yaml"
    text = case.read_text(encoding="utf-8").replace("end: 1\n", "end: 0.2\n")
    case.write_text(text.replace("step: 0.001\n", "step: 0.01\n"), encoding="utf-8")
    return set_file


def test_sweep_rates_span_half_to_one_and_a_half_times_the_nominal_rate() -> None:
    rates = sweep_rates(5)
    assert rates[0] == pytest.approx(math.pi) and rates[-1] == pytest.approx(3 * math.pi)
    assert rates[2] == pytest.approx(2 * math.pi)


def _set_runs_are_the_runs_alone(sweep: Path, executor: Executor) -> None:
    """Each run of the set, solved by `executor` (`solve_spec`, as `run_set` does) and
    written by this process, has the CSV of the same case run alone with
    `--set crank_rate=VALUE` (`run_file`), byte for byte."""
    compiled = load_and_compile_set(sweep)
    specs = list(compiled.runs)
    assert len(specs) == RUNS
    pooled = sweep.parent / "set"
    for index, outcome in executor.map_unordered(solve_spec, specs):
        assert outcome.solution.status == "ok" and outcome.name == specs[index].name
        write_results(outcome, pooled, version=compiled.version)
    for spec, rate in zip(specs, sweep_rates(RUNS)):
        alone = sweep.parent / "alone"
        (outcome,) = run_file(
            sweep.with_name("crank.case.yaml"),
            output_dir=alone,
            what_if=[Override(PARAMETER, repr(rate), rate)],
        )
        assert outcome.name == spec.name
        name = f"{spec.name}.csv"
        assert (alone / name).read_bytes() == (pooled / name).read_bytes()


def test_a_sweep_writes_the_bytes_of_each_run_alone(sweep: Path) -> None:
    _set_runs_are_the_runs_alone(sweep, SerialExecutor())


@pytest.mark.long  # worker start-up: about 10 s on a loaded 2-core machine
def test_a_sweep_on_a_pool_writes_the_bytes_of_each_run_alone(sweep: Path) -> None:
    _set_runs_are_the_runs_alone(sweep, PoolExecutor(2))


def test_the_accuracy_companion_skips_the_position_checks_only(sweep: Path, monkeypatch) -> None:
    """Without the checks after the run the companion has the same times and channels (the
    estimate uses nothing else) and does not run the toggle check the full solve runs (the
    free slider-crank passes its dead centres without a warning either way)."""
    import importlib

    solve = importlib.import_module("mechlib.solvers.solve")
    checked: list = []
    toggle_warnings = solve.toggle_warnings

    def counted(system, trajectory, *args):
        checked.append(len(trajectory))
        return toggle_warnings(system, trajectory, *args)

    monkeypatch.setattr(solve, "toggle_warnings", counted)
    built = build_run(load_case(sweep.with_name("crank.case.yaml")))
    analysis = coarser(built.analysis)
    full = built.solve(analysis)
    assert checked == [len(full.time)]
    bare = built.solve(analysis, checks=False)
    assert checked == [len(full.time)]
    assert (full.time == bare.time).all() and full.channels.keys() == bare.channels.keys()
    for column, values in full.channels.items():
        assert (values == bare.channels[column]).all(), column
    assert not any("near-singular" in w for w in full.warnings + bare.warnings)


def test_the_equal_accuracy_sweep_uses_the_suites_setting(tmp_path: Path) -> None:
    """`--equal-accuracy`: the case as the suite calibrated it against Exudyn (tolerance
    1e-4, steps landing on the outputs, no companion), still a valid case."""
    set_file = write_sweep(tmp_path, sweep_rates(2), equal=True)
    case = load_case(set_file.with_name("crank.case.yaml"))
    analysis = build_run(case).analysis
    assert analysis.tolerance == 1e-4 and not analysis.dense
    assert case.case.analysis.accuracy == "off"
