"""Issue 15 items 1 and 3: a value that turns non-finite while solving stops the run (exit 1)
naming the element, the time and the value, keeping the rows before it; never `status: ok`
with NaN rows. A request that fails at some time keeps the other columns and the rows."""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np

from loadcases.results.files import read_results
from tests.hardening.conftest import loads
from tests.loadcases.test_initial_modes import COUNT, _text

PUSH = '"-load"'


def _summary(folder: Path, name: str = "crank-turn") -> dict:
    return json.loads((folder / f"{name}.summary.json").read_text(encoding="utf-8"))


def test_force_overflowing_in_a_kinematic_run_fails_naming_element_time_value(
    crank, tmp_path: Path
) -> None:
    """t*1e300*1e10 is finite at t = 0 (0 N) and infinite from t = 0.05 s (5e308 N)."""
    case = crank(mech=(PUSH, '"t*1e300*1e10"'))
    result = loads("run", case, "-o", tmp_path / "out")
    assert result.exit_code == 1, result.output
    summary = _summary(tmp_path / "out")
    assert summary["status"] == "failed"
    assert summary["message"] == (
        "the solution is not finite at t = 0.05 s: force element "
        "'push' gives inf (not finite) there"
    )
    time, channels = read_results(tmp_path / "out" / "crank-turn.csv")
    assert time.tolist() == [0.0]
    assert all(np.isfinite(values).all() for values in channels.values())


def test_force_overflowing_in_a_dynamic_run_names_the_element(crank, tmp_path: Path) -> None:
    """A free crank under gravity; the push becomes infinite after t = 0.1 s: Newton fails,
    and the failure says which element gave a non-finite value."""
    case = crank(
        mech=(PUSH, '"(t > 0.1) * t*1e300*1e10"'),
        case=(
            'motions:\n  drive: {joint: pivot, value: "speed * t"}\nanalysis: {type: kinematic,',
            "analysis: {type: dynamic,",
        ),
    )
    text = case.read_text(encoding="utf-8").replace(
        "  drive_torque: {motion: drive, quantity: torque}\n", ""
    )
    case.write_text(text, encoding="utf-8")
    result = loads("run", case, "-o", tmp_path / "out")
    assert result.exit_code == 1, result.output
    summary = _summary(tmp_path / "out")
    assert summary["status"] == "failed"
    assert summary["message"].endswith(
        "; force element 'push' gives inf (not finite) at t = 0.1 s"
    ), summary["message"]
    time, channels = read_results(tmp_path / "out" / "crank-turn.csv")
    # rows at 0 and 0.05 s kept, and 0.1 s where a step happens to end on it (dense rows
    # come from the steps across them; the steps across 0.1 s fail): never one after it
    assert time[-1] <= 0.1 + 1e-12 and time.size in (2, 3) and time[:2].tolist() == [0.0, 0.05]
    assert all(np.isfinite(values).all() for values in channels.values())


def test_request_failing_at_some_time_keeps_other_columns_and_rows(crank, tmp_path: Path) -> None:
    """`1/(t - 0.2)` divides by zero at t = 0.2 s (5th row): its column holds the four values
    before and NaN after; the other columns are whole; the run is failed, the column named."""
    case = crank(
        case=(
            "  drive_torque: {motion: drive, quantity: torque}\n",
            "  drive_torque: {motion: drive, quantity: torque}\n"
            '  bad: {expression: "1/(t - 0.2)"}\n',
        )
    )
    result = loads("run", case, "-o", tmp_path / "out")
    assert result.exit_code == 1, result.output
    summary = _summary(tmp_path / "out")
    assert summary["status"] == "failed"
    assert summary["message"] == (
        "requests: requests.bad: division by zero at offset 1 at "
        "t = 0.2 s (column bad.value is empty from there on; the "
        "other columns are whole)"
    )
    time, channels = read_results(tmp_path / "out" / "crank-turn.csv")
    assert time.size == 11
    bad = channels.pop("bad.value")
    np.testing.assert_allclose(bad[:4], [1 / (t - 0.2) for t in time[:4]], rtol=1e-12)
    assert np.isnan(bad[4:]).all()
    assert all(np.isfinite(values).all() for values in channels.values())
    assert math.isclose(summary["extremes"]["bad.value"]["min"], 1 / (0.15 - 0.2), rel_tol=1e-9)


def test_request_turning_infinite_is_a_failure_naming_column(crank, tmp_path: Path) -> None:
    case = crank(
        case=(
            "  drive_torque: {motion: drive, quantity: torque}\n",
            "  drive_torque: {motion: drive, quantity: torque}\n"
            '  big: {expression: "t*1e300*1e10"}\n',
        )
    )
    result = loads("run", case, "-o", tmp_path / "out")
    assert result.exit_code == 1, result.output
    summary = _summary(tmp_path / "out")
    assert summary["status"] == "failed"
    assert summary["message"] == "column big.value is not finite (inf) at t = 0.05 s"


def test_a_huge_initial_modal_coordinate_fails_cleanly_saying_why(tmp_path: Path) -> None:
    """A modal coordinate of 1e300 (finite: no input error) takes the assembly's equations
    beyond doubles: the run fails (exit 1) saying the initial positions could not be
    assembled and which given value is the largest; no internal error, no RuntimeWarning."""
    modes = "[1e300" + ", 0" * (COUNT - 1) + "]"
    case = tmp_path / "beam.case.yaml"
    analysis = "analysis: {type: dynamic, end: 0.01, step: 0.001}"
    case.write_text(_text(f"initial:\n  beam: {{modes: {modes}}}\n{analysis}"), encoding="utf-8")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = loads("run", case, "-o", tmp_path / "out")
    assert result.exit_code == 1, result.output
    assert "internal error" not in result.output and "Warning" not in result.output
    assert not [w for w in caught if issubclass(w.category, RuntimeWarning)], caught
    summary = _summary(tmp_path / "out", "flexible-cantilever")
    assert summary["status"] == "failed"
    assert summary["message"] == (
        "the initial positions could not be assembled: the constraint equations on the way "
        "to the given values exceed the range of double-precision numbers (the largest given "
        "value: modal coordinate 1 of flexible body 'beam', 1e+300); give values the "
        "mechanism can reach"
    )
