"""Factors as the stress office uses them (case factors, limit and ultimate allowables,
the margin table), numerical noise (`~0`), the loads matrix and lean workbooks: numbers
against hand computations, workbooks read back with openpyxl."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import openpyxl
import pytest

from loadcases.report.decimate import CHART_ROWS, chart_rows, decimate_run
from loadcases.report.envelope import extract_envelope
from loadcases.report.loads_matrix import loads_matrix
from loadcases.report.margin_table import margin_lines
from loadcases.report.margins import apply_margins, case_factor
from loadcases.report.noise import noise_columns
from loadcases.report.peaks import run_peaks
from loadcases.results.files import read_results
from loadcases.results.saved import SavedRun
from loadcases.schema.setfile import Allowable
from loadcases.sets.campaign import run_set
from tests.loadcases.set_fixtures import write_inputs

UNITS = {"h.fx": "N", "h.fy": "N", "h.tz": "N*m", "g.fx": "N", "abscissa.value": "rad"}


def run(name: str, **channels: list[float]) -> SavedRun:
    values = {k.replace("__", "."): np.array(v, dtype=float) for k, v in channels.items()}
    size = len(next(iter(values.values())))
    return SavedRun(name, np.arange(size, dtype=float), values, units=dict(UNITS))


def _allowable(**values: object) -> Allowable:
    return Allowable.model_validate(values)


def test_case_factors_pick_the_governing_factored_load_and_both_margins() -> None:
    """Hand computation: ultimate 1.5, fitting 1.15 on h, freefall runs x 1.25.
    max side: retract 1000 x 1 = 1000 < freefall 900 x 1.25 = 1125 -> freefall governs,
    factor 1.5 x 1.15 x 1.25 = 2.15625, ultimate 900 x 2.15625 = 1940.625 N;
    MS ultimate = 2500 / 1940.625 - 1; MS limit = 1400 / (1.15 x 1.25 x 900) - 1.
    min side: retract -600 x 1 < freefall -400 x 1.25 = -500 -> retract governs,
    factor 1.725, MS ultimate = -1200 / (1.725 x -600) - 1."""
    runs = [
        run("retract[v=1]", h__fx=[0.0, 1000.0, -600.0]),
        run("freefall[v=1]", h__fx=[0.0, 900.0, -400.0]),
    ]
    allowables = {"h.fx": _allowable(ultimate={"max": 2500, "min": -1200}, limit=1400)}
    (row,) = apply_margins(
        extract_envelope(runs),
        {"ultimate": 1.5, "h": 1.15},
        allowables,
        case_factors={"freefall*": 1.25},
        peaks=run_peaks(runs),
    )
    assert row.max == 1000.0 and row.max_run == "retract[v=1]"  # the limit envelope
    assert row.ultimate_max_run == "freefall[v=1]"
    assert row.factor == pytest.approx(1.5 * 1.15 * 1.25, rel=1e-15)
    assert row.ultimate_max == pytest.approx(1940.625, rel=1e-14)
    assert row.ms_max == pytest.approx(2500 / 1940.625 - 1, rel=1e-14)
    assert row.limit_allowable_max == 1400.0 and row.limit_allowable_min == -1400.0
    assert row.ms_limit_max == pytest.approx(1400 / (1.15 * 1.25 * 900) - 1, rel=1e-14)
    assert row.ultimate_min_run == "retract[v=1]" and row.factor_min == pytest.approx(1.725)
    assert row.ultimate_min == pytest.approx(-1035.0, rel=1e-14)
    assert row.ms_min == pytest.approx(-1200 / -1035.0 - 1, rel=1e-14)
    assert row.ms_limit_min == pytest.approx(-1400 / (1.15 * -600) - 1, rel=1e-14)
    lines = margin_lines([row], ultimate=1.5)
    assert [line.ms for line in lines] == sorted(line.ms for line in lines)
    assert len(lines) == 4 and lines[0].ms == pytest.approx(row.ms_limit_max, rel=1e-14)
    first = lines[0]  # the lowest: limit, max side, 1400 / 1293.75 - 1 = 0.0821
    assert (first.kind, first.side, first.run) == ("limit", "max", "freefall[v=1]")
    assert first.factor == pytest.approx(1.4375, rel=1e-14)
    assert first.load == pytest.approx(900.0) and first.factored_load == pytest.approx(1293.75)


def test_without_case_factors_the_margins_are_unchanged() -> None:
    """Today's result: factor = ultimate x fitting on the envelope's max and min."""
    runs = [run("a", h__fx=[1000.0, -500.0]), run("b", h__fx=[200.0, -700.0])]
    (row,) = apply_margins(extract_envelope(runs), {"ultimate": 1.5}, {"h.fx": {"max": 3000.0}})
    assert row.factor == row.factor_min == 1.5
    assert (row.ultimate_max, row.ultimate_min) == (1500.0, -1050.0)
    assert row.ultimate_min_run == "b" and row.ms_max == pytest.approx(1.0)


def test_case_factor_matches_run_or_family_and_multiplies() -> None:
    factors = {"freefall-*": 1.25, "*[v=2]": 1.1, "retract": 1.05}
    assert case_factor("freefall-dyn[v=2]", "freefall-dyn", factors) == pytest.approx(1.375)
    assert case_factor("freefall-dyn[v=3]", "freefall-dyn", factors) == 1.25  # [ is literal
    assert case_factor("retract[v=1]", "retract", factors) == 1.05
    assert case_factor("other", "other", factors) == 1.0


def test_noise_at_the_threshold_of_the_request_and_of_the_set() -> None:
    """h.fy = 1e-6 x 2000 N is ~0 (at the floor), 1.01e-6 x 2000 N is not; h.tz (every
    moment of h round-off) is ~0 against the set's largest moment (k.tz, 500 N*m)."""
    at_floor = run("a", h__fx=[2000.0, 0.0], h__fy=[2e-3, 0.0], g__fx=[5.0, 1.0])
    above = run("a", h__fx=[2000.0, 0.0], h__fy=[2.02e-3, 0.0], g__fx=[5.0, 1.0])
    assert noise_columns(extract_envelope([at_floor])) == {"h.fy"}
    assert noise_columns(extract_envelope([above])) == set()
    assert noise_columns(extract_envelope([above]), fraction=1e-5) == {"h.fy"}
    # g.fx = 5 N is 2.5e-3 of the set's 2000 N: a real load of its own request
    moments = [
        run("m", h__fx=[1.0, 0.0], h__tz=[3e-9, 0.0]),
        SavedRun("t", np.array([0.0]), {"k.tz": np.array([500.0])}, units={"k.tz": "N*m"}),
    ]
    assert noise_columns(extract_envelope(moments)) == {"h.tz"}  # 6e-12 of 500 N*m
    rows = apply_margins(
        extract_envelope([at_floor]),
        {"ultimate": 1.5},
        {"h.fy": {"max": 1.0}},
        noise={"h.fy"},
    )
    fy = next(r for r in rows if r.column == "h.fy")
    assert fy.noise == "~0" and fy.factor is None and fy.ms_max is None
    assert fy.allowable_max == 1.0 and margin_lines(rows, 1.5) == []


def test_loads_matrix_cells_are_each_runs_peaks_with_the_critical_run() -> None:
    runs = [
        run("c[v=1]", h__fx=[1.0, 7.0, -2.0], abscissa__value=[0.0, 0.1, 0.2]),
        run("c[v=2]", h__fx=[3.0, -9.0, 4.0], abscissa__value=[0.0, 0.3, 0.6]),
        run("d", h__fx=[5.0, 6.0, 5.0]),
    ]
    matrix = loads_matrix(
        run_peaks(runs),
        [(r.name, r.family) for r in runs],
        units={"h.fx": "N"},
        at={"c": ("angle(hinge)", "rad")},
    )
    assert matrix.heads == ["c[v=1]", "c[v=2]", "d"]
    assert matrix.at == [("angle(hinge)", "rad")] * 2 + [("time", "s")]
    (row,) = [r for r in matrix.rows if r.column == "h.fx"]
    assert [(c.max, c.at("max"), c.min, c.at("min")) for c in row.cells] == [
        (7.0, 0.1, -2.0, 0.2),
        (4.0, 0.6, -9.0, 0.3),
        (6.0, 1.0, 5.0, 0.0),  # no abscissa: where is the time
    ]
    assert row.critical == {"max": 0, "min": 1}
    assert "abscissa.value" not in {r.column for r in matrix.rows}
    families = loads_matrix(
        run_peaks(runs),
        [(r.name, r.family) for r in runs],
        units={},
        at={},
        by="families",
    )
    assert families.heads == ["c", "d"]
    c = families.rows[0].cells[0]
    assert (c.max, c.run, c.min) == (7.0, "c[v=1]", -9.0)


def test_decimation_keeps_every_columns_peaks_exactly() -> None:
    rng = np.random.default_rng(7)
    size = 20_000
    channels = {f"r.c{k}": rng.normal(size=size) for k in range(6)}
    channels["r.c0"][12_345] = 99.0  # a spike between evenly spaced rows
    thin = decimate_run(SavedRun("r", np.linspace(0.0, 1.0, size), channels), skip={"r.c5"})
    assert "r.c5" not in thin.channels
    assert thin.time.size <= CHART_ROWS + 2 * 5
    for column, values in thin.channels.items():
        assert values.max() == channels[column].max() and values.min() == channels[column].min()
    assert thin.time[0] == 0.0 and thin.time[-1] == 1.0
    assert chart_rows(50, [np.zeros(50)]).tolist() == list(range(50))  # short runs: every row


LONG_SET = """\
set: long
cases: [crank.case.yaml]
parameters: {speed: 1.0}
sweep: {load: ["10 N", "20 N"]}
factors: {ultimate: 1.5}
case_factors: {"crank-*": 1.2}
allowables:
  drive_torque.value: {ultimate: 2.5, limit: {max: 1.6}}
report: {output: long.xlsx, units: {force: kN, torque: N*mm, angle: deg}, histories: HIST}
"""


def _long_set(tmp_path: Path, histories: str) -> Path:
    folder = write_inputs(tmp_path)
    case = (folder / "crank.case.yaml").read_text()
    (folder / "crank.case.yaml").write_text(case.replace("step: 0.05", "step: 0.0002"))
    (folder / "long.set.yaml").write_text(LONG_SET.replace("HIST", histories))
    return folder


@pytest.fixture(scope="module")
def long_set(tmp_path_factory: pytest.TempPathFactory):
    folder = _long_set(tmp_path_factory.mktemp("long"), "envelope")
    return run_set(folder / "long.set.yaml", output_dir=folder / "out")


def test_lean_workbook_histories_hold_the_chart_rows_and_every_peak(long_set) -> None:
    """2 runs of 2501 rows: each history sheet holds at most CHART_ROWS + 2 x columns rows,
    every column's max and min equal to the CSV's (in report units); the file stays small."""
    path = long_set.directory / "long.xlsx"
    assert path.stat().st_size < 150_000
    book = openpyxl.load_workbook(path)
    cases = {row[0]: row for row in book["Cases"].iter_rows(min_row=2, values_only=True)}
    for record in long_set.records:
        time, channels = read_results(record.csv_path)
        assert time.size == 2501
        sheet = book[cases[record.name][11]]
        header = [c.value for c in sheet[1]]
        rows = list(sheet.iter_rows(min_row=2, values_only=True))
        assert len(rows) <= CHART_ROWS + 2 * len(channels)
        column = header.index("drive_torque.value [N*mm]")
        values = [r[column] for r in rows]
        assert all(isinstance(v, float) for v in values)
        assert max(values) == pytest.approx(channels["drive_torque.value"].max() * 1e3, rel=1e-12)
        assert min(values) == pytest.approx(channels["drive_torque.value"].min() * 1e3, rel=1e-12)
        assert not any(h.startswith("pivot_force.fz") for h in header if h)  # ~0: left out
        assert cases[record.name][12] == record.csv_path.name


def test_margins_sheet_and_csv_lowest_first(long_set) -> None:
    """drive torque (crank of 1 kg, push `load` at 0.1 m): MS ultimate = 2.5 / (1.5 x 1.2 x
    max) - 1 and MS limit = 1.6 / (1.2 x max) - 1, the max read from the run's CSV."""
    peak = max(read_results(r.csv_path)[1]["drive_torque.value"].max() for r in long_set.records)
    with open(long_set.directory / "margins.csv", newline="") as handle:
        lines = list(csv.DictReader(handle))
    ms = [float(line["ms"]) for line in lines]
    assert ms == sorted(ms)
    by_kind = {(line["kind"], line["side"]): line for line in lines}
    ultimate = by_kind["ultimate", "max"]
    assert float(ultimate["factor"]) == pytest.approx(1.8, rel=1e-15)
    assert float(ultimate["ms"]) == pytest.approx(2.5 / (1.8 * peak) - 1, rel=1e-12)
    assert float(by_kind["limit", "max"]["ms"]) == pytest.approx(1.6 / (1.2 * peak) - 1, rel=1e-12)
    sheet = openpyxl.load_workbook(long_set.directory / "long.xlsx")["Margins"]
    header = [c.value for c in sheet[1]]
    first = dict(zip(header, (c.value for c in sheet[2])))
    assert first["ms"] == pytest.approx(min(ms), rel=1e-12)
    assert first["unit"] == "N*mm" and isinstance(first["load"], float)
    assert first["load"] == pytest.approx(float(lines[0]["load"]) * 1e3, rel=1e-12)


def test_loads_matrix_sheet_and_csv_equal_the_runs_peaks(long_set) -> None:
    with open(long_set.directory / "loads-matrix.csv", newline="") as handle:
        table = {row["column"]: row for row in csv.DictReader(handle)}
    sheet = openpyxl.load_workbook(long_set.directory / "long.xlsx")["Loads matrix"]
    heads = [c.value for c in sheet[1]]
    shown = {row[0].value: row for row in sheet.iter_rows(min_row=3)}
    for record in long_set.records:
        _time, channels = read_results(record.csv_path)
        for column, values in channels.items():
            if column == "abscissa.value":
                assert column not in table
                continue
            assert float(table[column][f"{record.name} max"]) == values.max()
            assert float(table[column][f"{record.name} min"]) == values.min()
            at = channels["abscissa.value"][int(np.argmax(values))]
            assert float(table[column][f"{record.name} max at"]) == at
        first = heads.index(record.name)
        cell = shown["drive_torque.value"][first]
        assert cell.value == pytest.approx(channels["drive_torque.value"].max() * 1e3, rel=1e-12)
        assert shown["pivot_force.fz"][first].value == "~0"
        at = shown["drive_torque.value"][first + 1].value
        row = int(np.argmax(channels["drive_torque.value"]))
        assert at == pytest.approx(math.degrees(channels["abscissa.value"][row]), abs=1e-12)
    assert table["pivot_force.fz"]["noise"] == "~0"
    critical = table["drive_torque.value"]["critical_max"]
    assert critical == long_set.records[-1].name  # the larger push load
    row = shown["drive_torque.value"]
    assert row[heads.index(critical)].fill.fgColor.rgb.endswith("F4B183")
    assert sheet["F2"].value == "at angle(pivot) [deg]"
    # each run's name centred across its four columns, no merged cells (quadratic to write)
    assert not sheet.merged_cells.ranges
    for record in long_set.records:
        first = heads.index(record.name)
        assert heads[first + 1 : first + 4] == [None, None, None]
        assert {c.alignment.horizontal for c in sheet[1][first : first + 4]} == {"centerContinuous"}


@pytest.mark.parametrize(("histories", "sheets"), [("all", 2), ("none", 0)])
def test_histories_all_or_none(tmp_path: Path, histories: str, sheets: int) -> None:
    folder = _long_set(tmp_path, histories)
    result = run_set(folder / "long.set.yaml", output_dir=folder / "out")
    book = openpyxl.load_workbook(result.directory / "long.xlsx", read_only=True)
    runs = [n for n in book.sheetnames if n.startswith("crank-turn(")]
    assert len(runs) == sheets
    if histories == "all":
        assert book[runs[0]].max_row == 2502  # header + every row


def test_allowables_limit_magnitude_and_one_ultimate_spelling(tmp_path: Path) -> None:
    from loadcases.foundation.diagnostics import InputError
    from loadcases.inputs.loader import load_set

    folder = write_inputs(tmp_path)
    good = folder / "good.set.yaml"
    good.write_text(
        "set: s\ncases: [crank.case.yaml]\nallowables:\n"
        "  drive_torque.value: {limit: 2 kN*m, ultimate: {max: 3 kN*m}}\n"
    )
    allowable = load_set(good).model.allowables["drive_torque.value"]
    assert allowable.limit_limits() == (2000.0, -2000.0)
    assert allowable.ultimate_limits() == (3000.0, None)
    bad = folder / "bad.set.yaml"
    bad.write_text(
        "set: s\ncases: [crank.case.yaml]\nallowables:\n"
        "  drive_torque.value: {max: 3, ultimate: 3}\n"
    )
    with pytest.raises(InputError) as error:
        load_set(bad)
    text = str(error.value)
    assert "bad.set.yaml:4:" in text and "give 'ultimate' or 'max'/'min', not both" in text


def test_a_case_factor_pattern_that_matches_no_case_is_an_error(tmp_path: Path) -> None:
    from loadcases.foundation.diagnostics import InputError
    from loadcases.sets.specs import load_and_compile_set

    folder = write_inputs(tmp_path)
    path = folder / "cf.set.yaml"
    body = "set: s\ncases: [crank.case.yaml]\nsweep: {speed: [1, 2]}\ncase_factors: {PATTERNS}\n"
    path.write_text(body.replace("PATTERNS", '"crank-*": 1.2, "crank-turn[speed=2]": 1.1'))
    assert len(load_and_compile_set(path).runs) == 2
    path.write_text(body.replace("PATTERNS", '"crank-trun": 1.2'))
    with pytest.raises(InputError) as error:
        load_and_compile_set(path)
    text = str(error.value)
    assert "cf.set.yaml:4:" in text and "unknown case 'crank-trun'" in text
    assert "did you mean 'crank-turn'" in text
