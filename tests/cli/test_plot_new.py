"""`loads new` and `loads plot` through the command line: exit status, files, messages."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from matplotlib.image import imread
from typer.testing import CliRunner

from cli.app import app
from loadcases.inputs.scaffold import SKELETONS

runner = CliRunner()


@pytest.mark.slow
def test_new_validate_run_plot_every_kind(tmp_path: Path) -> None:
    cases = tmp_path / "cases"
    for kind in SKELETONS:
        result = runner.invoke(app, ["new", kind, f"my-{kind}", "-o", str(cases)])
        assert result.exit_code == 0, result.output
        assert f"my-{kind}.case.yaml: {kind} case skeleton" in result.output
    files = sorted(str(p) for p in cases.glob("*.case.yaml"))
    assert len(files) == len(SKELETONS) == 8

    result = runner.invoke(app, ["validate", *files])
    assert result.exit_code == 0, result.output
    assert result.output.count(": ok") == 8

    # every skeleton runs in tests/loadcases/test_scaffold.py: here two through the CLI
    ran = ("blank", "lifting")
    out = tmp_path / "results"
    result = runner.invoke(
        app, ["run", *(str(cases / f"my-{k}.case.yaml") for k in ran), "-o", str(out)]
    )
    assert result.exit_code == 0, result.output
    requests = set()
    for kind in ran:
        summary = json.loads((out / f"my-{kind}.summary.json").read_text())
        assert summary["status"] == "ok", summary["message"]
        requests |= {column.rsplit(".", 1)[0] for column in summary["extremes"]}

    result = runner.invoke(app, ["plot", str(out), "-o", str(tmp_path / "png")])
    assert result.exit_code == 0, result.output
    pngs = sorted((tmp_path / "png").glob("*.png"))
    assert len(pngs) == len(requests)
    assert result.output.strip().endswith(f"{len(requests)} plots of 2 runs -> {tmp_path / 'png'}")
    assert imread(pngs[0]).shape[1] == 1000


def test_plot_one_run_against_a_column_and_chosen_columns(tmp_path: Path) -> None:
    assert runner.invoke(app, ["new", "rod-end", "duty", "-o", str(tmp_path)]).exit_code == 0
    out = tmp_path / "results"
    assert (
        runner.invoke(app, ["run", str(tmp_path / "duty.case.yaml"), "-o", str(out)]).exit_code == 0
    )
    result = runner.invoke(
        app,
        [
            "plot",
            str(out / "duty.csv"),
            "--x",
            "surface_angle.value",
            "--columns",
            "rod_end_force.f*,actuator_force",
            "-o",
            str(tmp_path / "png"),
        ],
    )
    assert result.exit_code == 0, result.output
    names = sorted(p.name for p in (tmp_path / "png").iterdir())
    assert names == [
        "actuator_force-vs-surface_angle.value.png",
        "rod_end_force-vs-surface_angle.value.png",
    ]
    # rod_end_force.fx fy fz f in N: one panel; 400 px high, 1000 px wide
    assert imread(tmp_path / "png" / names[1]).shape[:2] == (400, 1000)

    bad = runner.invoke(app, ["plot", str(out), "--columns", "nothing"])
    assert bad.exit_code == 2
    assert "loads: error: no column matches nothing (requests: rod_end_force" in bad.output


def test_new_refuses_to_overwrite_and_unknown_kinds(tmp_path: Path) -> None:
    first = runner.invoke(app, ["new", "opened", "stairs", "-o", str(tmp_path)])
    assert first.exit_code == 0
    before = (tmp_path / "stairs.case.yaml").read_text()
    again = runner.invoke(app, ["new", "jettison", "stairs", "-o", str(tmp_path)])
    assert again.exit_code == 2
    assert f"loads: error: {tmp_path / 'stairs.case.yaml'} exists: not overwritten" in again.output
    assert (tmp_path / "stairs.case.yaml").read_text() == before
    unknown = runner.invoke(app, ["new", "opend", "x", "-o", str(tmp_path)])
    assert unknown.exit_code == 2
    assert "unknown kind 'opend' (did you mean 'opened'?)" in unknown.output


def test_plot_missing_input_is_a_usage_error(tmp_path: Path) -> None:
    result = runner.invoke(app, ["plot", str(tmp_path / "nope")])
    assert result.exit_code == 2
    assert "no such file or folder" in result.output
    empty = runner.invoke(app, ["plot", str(tmp_path)])
    assert empty.exit_code == 2
    assert "no results" in empty.output
