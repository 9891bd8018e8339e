"""A set's `comparisons:` (loadcases.report.comparison): unknown runs and requests are input
errors naming the file, line and key. The comparison of a run set (comparisons.csv, the
`Comparison` sheet) is checked against the closed form in test_torque_margin_workbook.py,
on that file's set run."""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.diagnostics import InputError
from tests.loadcases.set_fixtures import TM_PANEL_CASE as CASE

SET = """\
set: cmp
cases: [panel.case.yaml]
sweep: {k_drive: [2, 0.1]}
comparisons:
  softer:
    reference: "torque-margin-panel[k_drive=2]"
    runs: ["torque-margin-panel[k_drive=0.1]"]
    columns: [spring, drive_torque.value]
report: {output: cmp.xlsx, units: {torque: N*mm}}
"""


def _inputs(folder: Path, set_text: str = SET) -> Path:
    text = CASE.read_text().replace("requests:\n", "requests:\n  spring: {force: drive}\n")
    (folder / "panel.case.yaml").write_text(text)
    (folder / "cmp.set.yaml").write_text(set_text)
    return folder / "cmp.set.yaml"


@pytest.mark.parametrize(
    "old, new, message",
    [
        (
            'runs: ["torque-margin-panel[k_drive=0.1]"]',
            'runs: ["panel[k_drive=0.1]"]',
            "unknown run",
        ),
        ("columns: [spring,", "columns: [sprung,", "unknown request 'sprung'"),
    ],
)
def test_unknown_names_are_input_errors(tmp_path: Path, old: str, new: str, message: str) -> None:
    from loadcases.sets.specs import load_and_compile_set

    path = _inputs(tmp_path, SET.replace(old, new))
    with pytest.raises(InputError) as error:
        load_and_compile_set(path)
    text = str(error.value)
    assert message in text and "comparisons.softer" in text and "cmp.set.yaml:" in text
