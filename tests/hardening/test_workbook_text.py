"""Issue 15 item 5: text from input files (run names, messages, columns ...) is written to
workbooks as text cells, never as formulas; read back with openpyxl, cell types checked."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import openpyxl
import pytest

from loadcases.draw.page import _title as page_title
from loadcases.foundation.clip import hidden_character
from loadcases.results.files import write_results
from loadcases.results.outcome import RunOutcome
from loadcases.sets import campaign
from loadcases.sets.campaign import run_set
from loadcases.sets.executors import SerialExecutor
from mechlib.core.outcome import Solution, SolverStats
from tests.hardening.conftest import loads
from tests.loadcases.set_fixtures import write_inputs

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


# Issue 39 item 3: hidden characters (controls, which make openpyxl refuse the whole
# workbook, and bidirectional controls, which reorder what a reader sees) are escapes.
HIDDEN = "diverged\x07 at \u202et = 0.1\nsee the log"
SHOWN = "diverged\\x07 at \\u202et = 0.1\\nsee the log"


def test_run_workbook_shows_hidden_characters_as_escapes(tmp_path: Path) -> None:
    write_results(_outcome("run", HIDDEN), tmp_path, xlsx=True, version="t")
    texts = {c.value for c in _cells(tmp_path / "run.xlsx") if isinstance(c.value, str)}
    assert SHOWN in texts
    assert not [t for t in texts if hidden_character(t)]


def test_a_set_with_a_failed_runs_message_writes_its_workbook_plots_and_csv(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A failed run's message goes into the set's workbook (sheet Cases): whatever it
    holds, the workbook, the plots and the CSV files of the set are written."""
    solve = campaign.solve_spec

    def failing(spec):
        outcome = solve(spec)
        if spec.name.endswith("[speed=2,load=10N]"):
            return campaign._failed_outcome(spec, "kinematic", HIDDEN)
        return outcome

    monkeypatch.setattr(campaign, "solve_spec", failing)
    folder = write_inputs(tmp_path)
    result = run_set(
        folder / "crank.set.yaml", output_dir=tmp_path / "out", executor=SerialExecutor()
    )
    assert len(result.failed) == 1
    book = tmp_path / "out" / "crank-set" / "crank-envelope.xlsx"
    texts = {c.value for c in _cells(book) if isinstance(c.value, str)}
    assert SHOWN in texts
    assert not [t for t in texts if hidden_character(t)]
    assert list((tmp_path / "out" / "crank-set").glob("envelope-*.png"))


def test_saved_runs_named_with_hidden_characters_give_clean_envelope_files(
    tmp_path: Path,
) -> None:
    """Saved results are not validated input: a hand-edited summary's name holding hidden
    characters reaches the envelope workbook and CSV as escapes."""
    for k, name in enumerate(["a\x07b", "c\u202ed", "e\nf"]):
        write_results(_outcome(name, "finished"), tmp_path / "runs" / f"r{k}", version="t")
    for out in ("env.xlsx", "env.csv"):
        result = loads("envelope", tmp_path / "runs", "-o", tmp_path / out)
        assert result.exit_code == 0, result.output
    texts = {c.value for c in _cells(tmp_path / "env.xlsx") if isinstance(c.value, str)}
    assert {"a\\x07b", "c\\u202ed", "e\\nf"} <= texts
    assert not [t for t in texts if hidden_character(t)]
    rows = (tmp_path / "env.csv").read_text(encoding="utf-8").splitlines()
    assert not [row for row in rows if hidden_character(row)]
    assert any("a\\x07b" in row for row in rows)


def test_html_page_title_shows_hidden_characters_as_escapes() -> None:
    traj = SimpleNamespace(case="crank<b>", reactions={}, status="failed", message=HIDDEN)
    title = page_title(traj, None)
    assert title == (
        "crank&lt;b&gt;<br><sub>the run failed: diverged\\x07 at \\u202et = 0.1\\nsee the log</sub>"
    )
