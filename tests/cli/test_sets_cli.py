"""`loads run SET.yaml` and `loads envelope` on set results: files, exit status, messages."""

from __future__ import annotations

import csv
from pathlib import Path

import openpyxl
from typer.testing import CliRunner

from cli.app import app
from tests.loadcases.set_fixtures import write_inputs

runner = CliRunner()


def test_run_set_writes_runs_envelope_and_workbook(tmp_path: Path) -> None:
    folder = write_inputs(tmp_path)
    out = tmp_path / "res"
    result = runner.invoke(
        app, ["run", str(folder / "crank.set.yaml"), "-o", str(out), "--jobs", "1"]
    )
    assert result.exit_code == 0, result.output
    set_dir = out / "crank-set"
    assert (set_dir / "crank-turn[speed=2,load=20N].csv").is_file()
    with open(set_dir / "envelope.csv", newline="") as stream:
        header = next(csv.reader(stream))
    assert header[:7] == ["column", "max", "max_run", "max_time", "min", "min_run", "min_time"]
    book = openpyxl.load_workbook(set_dir / "crank-envelope.xlsx")
    assert {"Cases", "Envelope", "Provenance"} <= set(book.sheetnames)
    assert "crank-set: 6 runs, 0 failed, 0 reused" in result.stdout
    again = runner.invoke(app, ["run", str(folder / "crank.set.yaml"), "-o", str(out)])
    assert again.exit_code == 0 and "6 reused" in again.stdout


def test_failing_run_gives_exit_1_and_is_listed(tmp_path: Path) -> None:
    folder = write_inputs(tmp_path)
    result = runner.invoke(
        app, ["run", str(folder / "slider.set.yaml"), "-o", str(tmp_path / "res"), "--jobs", "1"]
    )
    assert result.exit_code == 1
    assert "failed runs (1):" in result.stdout
    assert "slider-push[stroke=0.2]: position analysis did not converge" in result.stdout
    cases = openpyxl.load_workbook(tmp_path / "res" / "slider-set" / "slider.xlsx")["Cases"]
    statuses = [row[5] for row in cases.iter_rows(min_row=2, values_only=True)]
    assert statuses == ["ok", "failed", "ok"]


def test_invalid_set_exits_2_with_position(tmp_path: Path) -> None:
    folder = write_inputs(tmp_path)
    (folder / "bad.set.yaml").write_text(
        "set: bad\ncases: [crank.case.yaml]\nsweep: {lod: [1, 2]}\n", encoding="utf-8"
    )
    result = runner.invoke(app, ["run", str(folder / "bad.set.yaml"), "-o", str(tmp_path)])
    assert result.exit_code == 2
    assert "bad.set.yaml:3:9: error: sweep.lod: unknown parameter 'lod'" in result.stderr


def test_envelope_of_saved_set_results_with_set_margins(tmp_path: Path) -> None:
    folder = write_inputs(tmp_path)
    runner.invoke(
        app, ["run", str(folder / "crank.set.yaml"), "-o", str(tmp_path / "res"), "--jobs", "1"]
    )
    book = tmp_path / "env.xlsx"
    result = runner.invoke(
        app,
        [
            "envelope",
            str(tmp_path / "res"),
            "-o",
            str(book),
            "--set",
            str(folder / "crank.set.yaml"),
        ],
    )
    assert result.exit_code == 0, result.output
    with open(tmp_path / "res" / "crank-set" / "envelope.csv") as handle:
        saved = list(csv.DictReader(handle))
    sheet = openpyxl.load_workbook(book)["Envelope"]
    header = [c.value for c in sheet[1]]
    rows = [dict(zip(header, r)) for r in sheet.iter_rows(min_row=2, values_only=True)]
    torque = next(r for r in rows if r["column"] == "drive_torque.value")
    expected = next(r for r in saved if r["column"] == "drive_torque.value")
    assert torque["ms_max"] == float(expected["ms_max"])
    assert torque["max_run"] == expected["max_run"]


def test_file_kind_decided_alike_by_run_and_validate(tmp_path: Path) -> None:
    """A set named without `.set.yaml` runs as a set; a file whose kind cannot be told gets
    the same diagnostic from `run` and `validate` (one function decides the kind)."""
    folder = write_inputs(tmp_path)
    plain = folder / "crank-set.yaml"
    plain.write_text((folder / "crank.set.yaml").read_text(encoding="utf-8"), encoding="utf-8")
    result = runner.invoke(app, ["run", str(plain), "-o", str(tmp_path / "res"), "--jobs", "1"])
    assert result.exit_code == 0, result.output
    assert "crank-set: 6 runs, 0 failed, 0 reused" in result.stdout
    unknown = folder / "notes.yaml"
    unknown.write_text("colour: blue\n", encoding="utf-8")
    expected = [
        f"{unknown}:1:1: error: cannot tell the file kind",
        f"{unknown}:1:1: hint: name it *.mech.yaml, *.case.yaml or *.set.yaml",
    ]
    ran = runner.invoke(app, ["run", str(unknown), "-o", str(tmp_path / "res")])
    assert ran.exit_code == 2 and ran.stderr.splitlines() == expected
    checked = runner.invoke(app, ["validate", str(unknown)])
    assert checked.exit_code == 2 and checked.stdout.splitlines() == expected


def test_a_set_prints_each_runs_warnings_as_a_case_run_does(tmp_path: Path) -> None:
    """A set of two library cases, each with a warning: the pendulum at tolerance 1e-3 with
    an accuracy target of 1e-6 misses it (not tightened: a tolerance fixes the steps: the
    solver's warning), the kinematic slider-crank with an accuracy target (an input
    warning, with its place in the case file). The set prints each run's warnings under
    its status line as `loads run` of the case file prints them; a reused run prints its
    summary's (the input's as `key: message`)."""
    import shutil

    import yaml

    library = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification"
    shutil.copy(library / "slider_crank.mech.yaml", tmp_path)
    cases = {"pendulum": {"end": 0.5, "step": 0.01, "tolerance": 1e-3, "accuracy": 1e-6}}
    cases["slider_crank"] = {"accuracy": 1e-2}
    names = {}
    for stem, keys in cases.items():
        case = yaml.safe_load((library / f"{stem}.case.yaml").read_text(encoding="utf-8"))
        case["analysis"].update(keys)
        names[stem] = case["case"]
        (tmp_path / f"{stem}.case.yaml").write_text(yaml.safe_dump(case), encoding="utf-8")
    (tmp_path / "two.set.yaml").write_text(
        "set: two\ncases: [pendulum.case.yaml, slider_crank.case.yaml]\n", encoding="utf-8"
    )

    def warned(output: str, name: str) -> list[str]:
        lines = output.splitlines()
        first = next(i for i, line in enumerate(lines) if line.startswith(name))
        after = lines[first + 1 :]
        ends = [i for i, line in enumerate(after) if not line.startswith("  ")]
        return after[: ends[0] if ends else len(after)]

    alone = {}
    for stem, name in names.items():
        result = runner.invoke(
            app, ["run", str(tmp_path / f"{stem}.case.yaml"), "-o", str(tmp_path / "a")]
        )
        assert result.exit_code == 0, result.output
        alone[stem] = warned(result.stdout, name)
    assert any("accuracy: estimated error" in line for line in alone["pendulum"])
    assert any(
        "slider_crank.case.yaml:" in line and "analysis.accuracy" in line
        for line in alone["slider_crank"]
    )
    solved = runner.invoke(app, ["run", str(tmp_path / "two.set.yaml"), "-o", str(tmp_path / "b")])
    assert solved.exit_code == 0, solved.output
    for stem, name in names.items():
        assert warned(solved.stdout, name) == alone[stem]
    reused = runner.invoke(app, ["run", str(tmp_path / "two.set.yaml"), "-o", str(tmp_path / "b")])
    assert warned(reused.stdout, names["pendulum"]) == alone["pendulum"]
    assert any(
        line.startswith("  warning: analysis.accuracy")
        for line in warned(reused.stdout, names["slider_crank"])
    )
