"""The estimate-overhead benchmark's two variants of a case: the same run, with and without
its error estimate. No test here measures time."""

from __future__ import annotations

import numpy as np

from benchmarks.estimate_overhead import variants
from loadcases.run import run_case


def test_the_variants_differ_by_the_estimate_alone() -> None:
    """The pendulum cut to 2 s (the cost table's keys): as written it carries its accuracy
    estimate (a grid companion), off none; the run itself is the same to the last bit."""
    files = variants("pendulum 2 s")
    written, off = (run_case(files[kind]) for kind in ("as_written", "off"))
    assert written.solution.time[-1] == off.solution.time[-1] == 2.0
    assert written.checks["accuracy"]["companion"] == "grid"
    assert "accuracy" not in off.checks
    for column, values in off.solution.channels.items():
        np.testing.assert_array_equal(written.solution.channels[column], values)


def test_the_command_files_load_with_their_keys(tmp_path) -> None:
    """`--command`'s two case files load with their cost-table keys: the pendulum cut to
    2 s, as written and off; A01 with its mechanism file found beside its copy."""
    from benchmarks.estimate_overhead import command_files
    from loadcases.inputs.loader import load_case

    files = command_files("pendulum 2 s", tmp_path / "pendulum")
    written, off = (load_case(files[kind]) for kind in ("as_written", "off"))
    assert written.case.analysis.end == off.case.analysis.end == 2.0
    assert written.case.analysis.accuracy != "off"
    assert off.case.analysis.accuracy == "off"
    a01 = command_files("A01 10 s", tmp_path / "a01")
    loaded = load_case(a01["off"])
    assert loaded.case.analysis.end == 10.0 and loaded.case.analysis.accuracy == "off"
    assert loaded.mechanism_path is not None
