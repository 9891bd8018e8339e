"""The accuracy verdict of a dynamic run in its workbooks (it was only in the summary):
the per-run `NAME.xlsx` (`loads run --xlsx`) has on its Summary sheet the summary's
`accuracy` target, met, outcome and settings and the estimate per request (fractions of
the request's peak); a set's workbook has the target, met and outcome of every run on its
Cases sheet, as `loads envelope -o FILE.xlsx` from the saved summaries. Text is text,
never a formula."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import openpyxl
import pytest
from typer.testing import CliRunner

from cli.app import app
from loadcases.report.workbook_sheets import CASES_COLUMNS
from loadcases.results.files import write_results
from loadcases.results.outcome import RunOutcome
from mechlib.core.outcome import Solution, SolverStats

LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification"
runner = CliRunner()


@pytest.fixture(scope="module")
def pendulum(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The library pendulum over 1 s at 0.01 s outputs, with `accuracy: 1e-2`, and a set of
    it."""
    text = (LIBRARY / "pendulum.case.yaml").read_text(encoding="utf-8")
    text = text.replace("end: 4.0 ", "end: 1.0 ").replace("step: 0.001 ", "step: 0.01 ")
    text = text.replace("  step: 0.01 ", "  accuracy: 1e-2\n  step: 0.01 ")
    folder = tmp_path_factory.mktemp("pendulum")
    (folder / "pendulum.case.yaml").write_text(text, encoding="utf-8")
    (folder / "p.set.yaml").write_text("set: p\ncases: [pendulum.case.yaml]\n", encoding="utf-8")
    return folder


def _rows(path: Path, sheet: str) -> list[tuple[Any, ...]]:
    return list(openpyxl.load_workbook(path)[sheet].iter_rows(values_only=True))


def _summary_sheet(path: Path) -> dict[str, tuple[Any, ...]]:
    """The Summary sheet's lines by their first cell."""
    return {row[0]: row[1:] for row in _rows(path, "Summary") if row[0] is not None}


def test_a_runs_workbook_has_its_accuracy(pendulum: Path, tmp_path: Path) -> None:
    result = runner.invoke(
        app, ["run", str(pendulum / "pendulum.case.yaml"), "-o", str(tmp_path), "--xlsx"]
    )
    assert result.exit_code == 0, result.output
    base = tmp_path / "pendulum-release-60deg"
    accuracy = json.loads(Path(f"{base}.summary.json").read_text())["accuracy"]
    lines = _summary_sheet(Path(f"{base}.xlsx"))
    assert lines["accuracy.target"][:2] == (0.01, "of each request's peak")
    assert lines["accuracy.met"][0] == ("yes" if accuracy["met"] else "no")
    assert lines["accuracy.outcome"][0] == accuracy["outcome"]
    assert lines["accuracy.measure"][0] == "peaks"
    assert lines["accuracy.integrator"][0] == "generalized-alpha"
    assert lines["accuracy.tolerance"][0] == accuracy["tolerance"]
    assert lines["accuracy.cpu_seconds"][:2] == (accuracy["cpu_seconds"], "s")
    assert lines["request"][:3] == ("history (of peak)", "peak (of peak)", "sampling (of peak)")
    estimate = accuracy["estimate"]
    assert set(estimate) == {"hinge_angle", "hinge_rate", "hinge_force", "tip_pos"}
    for request, errors in estimate.items():
        shown = lines[request][:3]
        assert shown == (errors["history"], errors["peak"], errors["sampling"])
        assert 0.0 < errors["peak"] < 0.01  # met: every envelope peak within 1e-2


def _outcome(accuracy: dict[str, Any]) -> RunOutcome:
    time = np.linspace(0.0, 1.0, 3)
    solution = Solution(
        status="ok",
        message="finished",
        analysis="dynamic",
        time=time,
        channels={"arm.value": time.copy()},
        stats=SolverStats(steps=2, cpu_seconds=0.1),
    )
    return RunOutcome(
        name="arm",
        case_file=Path("arm.case.yaml"),
        analysis="dynamic",
        solution=solution,
        input_sha256="ab" * 32,
        column_units={"arm.value": "rad"},
        checks={"accuracy": accuracy},
    )


@pytest.mark.parametrize("text", ["=1+1", "+1", "-1", "@SUM(A1)"])
def test_accuracy_text_is_text_never_a_formula(tmp_path: Path, text: str) -> None:
    accuracy = {"target": 1e-3, "met": None, "outcome": text, "estimate": {}}
    write_results(_outcome(accuracy), tmp_path, xlsx=True, version="0")
    sheet = openpyxl.load_workbook(tmp_path / "arm.xlsx")["Summary"]
    cells = {row[0].value: row[1] for row in sheet.iter_rows() if row[0].value}
    assert cells["accuracy.outcome"].value == text
    assert cells["accuracy.outcome"].data_type == "s"
    assert cells["accuracy.met"].value == "not estimated"
    assert "request" not in cells  # nothing estimated: no table


def _cases(path: Path) -> dict[str, dict[str, Any]]:
    rows = _rows(path, "Cases")
    assert rows[0][: len(CASES_COLUMNS)] == CASES_COLUMNS
    return {row[0]: dict(zip(CASES_COLUMNS, row)) for row in rows[1:]}


def test_a_sets_workbook_has_each_runs_verdict(pendulum: Path, tmp_path: Path) -> None:
    out = tmp_path / "res"
    result = runner.invoke(
        app, ["run", str(pendulum / "p.set.yaml"), "-o", str(out), "--jobs", "1"]
    )
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "p" / "pendulum-release-60deg.summary.json").read_text())
    accuracy = summary["accuracy"]
    expected = (0.01, "yes" if accuracy["met"] else "no", accuracy["outcome"])
    columns = ("accuracy target (of peak)", "accuracy met", "accuracy outcome")
    run = _cases(out / "p" / "envelope.xlsx")["pendulum-release-60deg"]
    assert tuple(run[c] for c in columns) == expected
    saved = runner.invoke(app, ["envelope", str(out / "p"), "-o", str(tmp_path / "e.xlsx")])
    assert saved.exit_code == 0, saved.output
    run = _cases(tmp_path / "e.xlsx")["pendulum-release-60deg"]
    assert tuple(run[c] for c in columns) == expected


def test_a_saved_accuracy_block_is_checked(tmp_path: Path) -> None:
    """A summary whose `accuracy` the workbook cannot read is an input error naming it."""
    write_results(_outcome({"target": 1e-3, "met": True, "outcome": "met"}), tmp_path, version="0")
    path = tmp_path / "arm.summary.json"
    summary = json.loads(path.read_text())
    summary["accuracy"]["target"] = "1e-3"
    path.write_text(json.dumps(summary, indent=2))
    result = runner.invoke(app, ["envelope", str(tmp_path), "-o", str(tmp_path / "e.xlsx")])
    assert result.exit_code == 2
    assert "arm.summary.json:" in result.stderr
    assert "error: accuracy: must be an object with a finite number target" in result.stderr
