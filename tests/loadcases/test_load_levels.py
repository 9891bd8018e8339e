"""Load levels (`level: limit | ultimate` of a case): a set's ultimate factor multiplies the
limit-level runs only; an ultimate-level run's limit loads are its computed loads divided by
the factor. Numbers by hand: factor 1.5, fitting 1.15 on `rod`."""

from __future__ import annotations

import csv
import io

import numpy as np
import pytest

from loadcases.report.levels import at_limit_level
from loadcases.report.loads_matrix import matrix_csv_text
from loadcases.report.sizing import size_runs
from loadcases.results.saved import SavedRun
from loadcases.schema.case import CaseModel
from loadcases.schema.setfile import SetModel

UNITS = {"time": "s", "rod.f": "N", "hinge.value": "rad"}


def _run(name: str, peak: float, level: str) -> SavedRun:
    time = np.linspace(0.0, 1.0, 5)
    channels = {
        "rod.f": peak * np.array([0.1, 0.5, 1.0, 0.5, 0.2]),
        "hinge.value": np.linspace(0.0, 1.0, 5),
    }
    return SavedRun(name, time, channels, dict(UNITS), level=level)


def _set(**factors: float) -> SetModel:
    return SetModel.model_validate(
        {"set": "s", "cases": ["x"], "factors": factors, "allowables": {"rod.f": {"max": 3000.0}}}
    )


def test_case_level_defaults_to_limit_and_refuses_other_words():
    base = {"case": "c", "mechanism": "m.mech.yaml", "analysis": {"type": "static"}}
    assert CaseModel.model_validate(base).level == "limit"
    assert CaseModel.model_validate({**base, "level": "ultimate"}).level == "ultimate"
    with pytest.raises(ValueError, match="level"):
        CaseModel.model_validate({**base, "level": "design"})


def test_ultimate_level_run_is_factored_once():
    """Limit run 1000 N, ultimate run 1800 N computed: limits 1000 and 1200 N; the
    ultimate-level run governs with ultimate 1800 N (not 1.5 x 1800 = 2700 N)."""
    runs = [_run("lim", 1000.0, "limit"), _run("ult", 1800.0, "ultimate")]
    sizing = size_runs(runs, _set(ultimate=1.5))
    row = next(r for r in sizing.rows if r.column == "rod.f")
    assert (row.max, row.max_run, row.max_level) == (pytest.approx(1200.0), "ult", "ultimate")
    assert row.ultimate_max == pytest.approx(1800.0, rel=1e-15)
    assert row.ms_max == pytest.approx(3000.0 / 1800.0 - 1.0, rel=1e-14)
    angle = next(r for r in sizing.rows if r.column == "hinge.value")
    assert angle.max == 1.0 and angle.ultimate_max is None  # not a load: as computed
    assert runs[1].channels["rod.f"].max() == 1800.0  # the caller's run untouched


def test_limit_level_run_governs_when_larger():
    """Limit 1300 N against the ultimate run's 1800 / 1.5 = 1200 N: 1.5 x 1300 = 1950 N."""
    runs = [_run("lim", 1300.0, "limit"), _run("ult", 1800.0, "ultimate")]
    row = next(r for r in size_runs(runs, _set(ultimate=1.5)).rows if r.column == "rod.f")
    assert (row.max_run, row.max_level) == ("lim", "limit")
    assert row.ultimate_max == pytest.approx(1950.0, rel=1e-15)


def test_fitting_factor_still_applies_to_ultimate_level_loads():
    runs = [_run("ult", 1800.0, "ultimate")]
    row = next(r for r in size_runs(runs, _set(ultimate=1.5, rod=1.15)).rows if r.column == "rod.f")
    assert row.max == pytest.approx(1200.0)
    assert row.ultimate_max == pytest.approx(1.15 * 1800.0, rel=1e-14)


def test_loads_matrix_shows_limit_and_ultimate_of_every_run():
    runs = [_run("lim", 1000.0, "limit"), _run("ult", 1800.0, "ultimate")]
    sizing = size_runs(runs, _set(ultimate=1.5))
    table = list(csv.DictReader(io.StringIO(matrix_csv_text(sizing.matrix))))
    rod = next(line for line in table if line["column"] == "rod.f")
    assert float(rod["lim max"]) == pytest.approx(1000.0)
    assert float(rod["ult max"]) == pytest.approx(1200.0)
    assert float(rod["lim ultimate max"]) == pytest.approx(1500.0)
    assert float(rod["ult ultimate max"]) == pytest.approx(1800.0, rel=1e-15)
    assert (rod["lim level"], rod["ult level"]) == ("limit", "ultimate")
    angle = next(line for line in table if line["column"] == "hinge.value")
    assert angle["ult ultimate max"] == "" and float(angle["ult max"]) == 1.0
    assert rod["critical_max"] == "ult"


def test_without_ultimate_factor_limit_equals_computed():
    runs = [_run("ult", 1800.0, "ultimate")]
    assert at_limit_level(runs, {})[0] is runs[0]
    row = next(r for r in size_runs(runs, _set()).rows if r.column == "rod.f")
    assert row.max == 1800.0 and row.ultimate_max == 1800.0


def _level_set(folder, level: str, factors: str) -> list[str]:
    from set_fixtures import write_inputs

    from loadcases.inputs.loader import validate_files

    write_inputs(folder)
    case = (folder / "crank.case.yaml").read_text(encoding="utf-8")
    case = case.replace("mechanism: crank.mech.yaml", f"mechanism: crank.mech.yaml\nlevel: {level}")
    (folder / "crank.case.yaml").write_text(case, encoding="utf-8")
    text = f"set: s\ncases: [crank.case.yaml]\n{factors}report: {{output: s.xlsx}}\n"
    (folder / "s.set.yaml").write_text(text, encoding="utf-8")
    return [d.format() for d in validate_files([folder / "s.set.yaml"])]


def test_ultimate_case_without_ultimate_factor_warns(tmp_path):
    (message,) = _level_set(tmp_path, "ultimate", "")
    assert "warning" in message and "case 'crank-turn' gives its loads at ultimate level" in message
    assert "s.set.yaml:2:" in message


@pytest.mark.parametrize(
    ("level", "factors"), [("ultimate", "factors: {ultimate: 1.5}\n"), ("limit", "")]
)
def test_no_level_warning_when_harmless(tmp_path, level, factors):
    assert _level_set(tmp_path, level, factors) == []


def test_loads_matrix_ultimate_takes_case_and_fitting_factors():
    """ult: 1800 N computed at ultimate level, case factor 1.25, fitting 1.15 on rod:
    ultimate 1.25 x 1.15 x 1800 N; lim: 1000 N at limit level: 1.5 x 1.15 x 1000 N."""
    model = SetModel.model_validate(
        {
            "set": "s",
            "cases": ["x"],
            "factors": {"ultimate": 1.5, "rod": 1.15},
            "case_factors": {"ult": 1.25},
        }
    )
    sizing = size_runs([_run("lim", 1000.0, "limit"), _run("ult", 1800.0, "ultimate")], model)
    table = list(csv.DictReader(io.StringIO(matrix_csv_text(sizing.matrix))))
    rod = next(line for line in table if line["column"] == "rod.f")
    assert float(rod["ult ultimate max"]) == pytest.approx(1.25 * 1.15 * 1800.0, rel=1e-14)
    assert float(rod["lim ultimate max"]) == pytest.approx(1.5 * 1.15 * 1000.0, rel=1e-14)
