"""Issue 15 item 5: text from input files (run names, messages, columns ...) is written to
workbooks as text cells, never as formulas; read back with openpyxl, cell types checked."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import openpyxl

from loadcases.results.files import write_results
from loadcases.results.outcome import RunOutcome
from mechlib.core.outcome import Solution, SolverStats
from tests.hardening.conftest import loads

HOSTILE = ["=1+2", "+SUM(1,2)", "-2+3", "@SUM(1)", "=cmd|' /C calc'!A0", "#N/A"]


def _outcome(name: str, message: str) -> RunOutcome:
    solution = Solution(
        status="ok",
        message=message,
        analysis="kinematic",
        time=np.array([0.0, 0.1]),
        channels={"f.fx": np.array([1.0, -2.0])},
        stats=SolverStats(steps=2, cpu_seconds=0.1),
    )
    return RunOutcome(name, Path(f"{name}.case.yaml"), "kinematic", solution, "0" * 64)


def _cells(path: Path) -> list:
    workbook = openpyxl.load_workbook(path)
    return [
        cell
        for sheet in workbook.worksheets
        for row in sheet.iter_rows()
        for cell in row
        if cell.value is not None
    ]


def test_run_workbook_writes_hostile_text_as_text(tmp_path: Path) -> None:
    write_results(_outcome("=1+2", '=HYPERLINK("http://x")'), tmp_path, xlsx=True, version="t")
    cells = _cells(tmp_path / "=1+2.xlsx")
    assert not [c.coordinate for c in cells if c.data_type in ("f", "e")]
    texts = {c.value: c.data_type for c in cells if isinstance(c.value, str)}
    assert texts["=1+2"] == "s"
    assert texts['=HYPERLINK("http://x")'] == "s"


def test_envelope_workbook_of_saved_runs_writes_names_as_text(tmp_path: Path) -> None:
    """Saved results are not validated input: their names reach the workbook as written."""
    for k, name in enumerate(HOSTILE):
        write_results(_outcome(name, "finished"), tmp_path / "runs" / f"r{k}", version="t")
    result = loads("envelope", tmp_path / "runs", "-o", tmp_path / "env.xlsx")
    assert result.exit_code == 0, result.output
    cells = _cells(tmp_path / "env.xlsx")
    assert not [c.coordinate for c in cells if c.data_type in ("f", "e")]
    found = {c.value for c in cells if c.data_type == "s"}
    assert set(HOSTILE) <= found
