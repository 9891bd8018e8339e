"""A set's `comparisons:` (loadcases.report.comparison): unknown runs and requests are input
errors naming the file, line and key. The comparison of a run set (comparisons.csv, the
`Comparison` sheet) is checked against the closed form in test_torque_margin_workbook.py,
on that file's set run."""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.foundation.diagnostics import InputError
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


def test_peaks_ratios_and_round_off() -> None:
    """Signed peak of largest magnitude and its time; ratio run / reference; a reference
    peak at round-off (1e-23 beside 0.7) gives no ratio; a missing column no peak."""
    import numpy as np

    from loadcases.report.comparison import comparison_rows
    from loadcases.results.saved import SavedRun
    from loadcases.schema.setfile import Comparison

    t = np.array([0.0, 1.0, 2.0])
    rigid = SavedRun("rigid", t, {"m.value": np.array([10.0, -80.0, 60.0]), "z.value": t * 1e-23})
    flex = SavedRun("flex", t, {"m.value": np.array([5.0, 40.0, -60.0]), "z.value": t * 0.35})
    spec = Comparison(reference="rigid", runs=["flex", "gone"], columns=["m", "z.value"])
    rows = {(r.column, r.run): r for r in comparison_rows({"c": spec}, [rigid, flex])}
    assert (rows["m.value", "rigid"].peak, rows["m.value", "rigid"].time) == (-80.0, 1.0)
    assert rows["m.value", "flex"].ratio == pytest.approx(0.75, rel=1e-15)
    assert rows["z.value", "flex"].peak == 0.7 and rows["z.value", "flex"].ratio is None
    assert rows["m.value", "gone"].peak is None and rows["m.value", "gone"].ratio is None


def test_a_pair_compares_two_columns_for_one_quantity(tmp_path: Path) -> None:
    """`REF = -RUN`: the reference's REF beside the runs' RUN negated (a latch spring's
    torque against a locked joint's reaction on the other body); an unknown request on
    either side is an input error."""
    import numpy as np

    from loadcases.report.comparison import comparison_rows
    from loadcases.results.saved import SavedRun
    from loadcases.schema.setfile import Comparison
    from loadcases.sets.specs import load_and_compile_set

    t = np.array([0.0, 1.0])
    rigid = SavedRun("rigid", t, {"latch.value": np.array([0.0, 20.0])})
    flex = SavedRun("flex", t, {"lock.tz": np.array([0.0, -17.0])})
    spec = Comparison(reference="rigid", runs=["flex"], columns=["latch.value = -lock.tz"])
    rows = {r.run: r for r in comparison_rows({"c": spec}, [rigid, flex])}
    assert rows["rigid"].column == "latch.value = -lock.tz" and rows["rigid"].peak == 20.0
    assert (rows["flex"].peak, rows["flex"].ratio) == (17.0, pytest.approx(0.85, rel=1e-15))
    path = _inputs(tmp_path, SET.replace("columns: [spring,", "columns: [spring = -sprung,"))
    with pytest.raises(InputError, match="unknown request 'sprung'"):
        load_and_compile_set(path)
