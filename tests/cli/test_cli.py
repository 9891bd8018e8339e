"""The `loads` command line (SPEC section 2): outputs and exit status of every command."""

from __future__ import annotations

import functools
import importlib
import io
import json
import re
import sys
import types
from pathlib import Path

import numpy as np
import openpyxl
import pytest
from typer.testing import CliRunner

import cli.app as cli_app
from cli.app import app
from cli.engine import Engine
from cli.render import ProgressBar
from cli.set_runner import SetProgress
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.results.files import write_results
from loadcases.results.outcome import RunOutcome
from mechlib.core.outcome import Solution, SolverStats

runner = CliRunner()


def outcome(name: str, status: str = "ok", scale: float = 1.0) -> RunOutcome:
    """A two-row outcome with one channel."""
    solution = Solution(
        status=status,
        message="ok" if status == "ok" else "singular at t = 0.1 s",
        analysis="kinematic",
        time=np.array([0.0, 0.1]),
        channels={"pivot_force.fx": scale * np.array([1.0, -2.0])},
        stats=SolverStats(steps=11, cpu_seconds=0.5),
    )
    return RunOutcome(name, Path(f"{name}.case.yaml"), "kinematic", solution, "0" * 64)


def fake_run_file(
    path: Path, *, output_dir: Path, xlsx: bool = False, progress=None, behaviour: dict[str, object]
):
    """A `run_file` that looks up each file's name in `behaviour` (outcomes or an exception)."""
    what = behaviour[Path(path).name]
    if isinstance(what, Exception):
        raise what
    outcomes = list(what)
    for item in outcomes:
        write_results(item, output_dir, xlsx=xlsx, version="test")
    return outcomes


def fake_engine(behaviour: dict[str, object]) -> Engine:
    """The engine `loads run` is given instead of loadcases' (picklable: `--jobs` sends it)."""
    return Engine(run_file=functools.partial(fake_run_file, behaviour=behaviour))


def case_files(tmp_path: Path, *names: str) -> list[str]:
    for name in names:
        (tmp_path / name).write_text(f"case: {name.split('.')[0]}\n")  # names must differ
    return [str(tmp_path / name) for name in names]


def test_run_ok_prints_status_and_writes_results(tmp_path: Path) -> None:
    engine = fake_engine({"a.case.yaml": [outcome("a")]})
    out = tmp_path / "res"
    result = runner.invoke(
        app, ["run", *case_files(tmp_path, "a.case.yaml"), "-o", str(out)], obj=engine
    )
    assert result.exit_code == 0, result.output
    assert f"a: ok, 11 steps, cpu 0.5 s -> {out / 'a.csv'}" in result.stdout
    assert (out / "a.csv").is_file() and (out / "a.summary.json").is_file()


def test_run_prints_input_and_solver_warnings(tmp_path: Path) -> None:
    """The input's warnings reach the CLI as data, printed as `loads validate` prints them
    (`file:line:col: warning: key: message`, and the hint's line), the solver's as its
    messages; both under the run's status line."""
    run = outcome("a")
    run.warnings.append(
        Diagnostic(
            "a.case.yaml",
            3,
            27,
            "effects.friktion",
            "unknown effect 'friktion'",
            "warning",
            "did you mean 'friction'?",
        )
    )
    run.solution.warnings.append("near-singular at t = 0.05 s")
    result = runner.invoke(
        app,
        ["run", *case_files(tmp_path, "a.case.yaml"), "-o", str(tmp_path / "r")],
        obj=fake_engine({"a.case.yaml": [run]}),
    )
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines()[1:] == [
        "  a.case.yaml:3:27: warning: effects.friktion: unknown effect 'friktion'",
        "  a.case.yaml:3:27: hint: did you mean 'friction'?",
        "  warning: near-singular at t = 0.05 s",
    ]


def test_run_solver_failure_exits_1(tmp_path: Path) -> None:
    engine = fake_engine(
        {"a.case.yaml": [outcome("a")], "b.case.yaml": [outcome("b", status="failed")]}
    )
    files = case_files(tmp_path, "a.case.yaml", "b.case.yaml")
    result = runner.invoke(app, ["run", *files, "-o", str(tmp_path / "r"), "--xlsx"], obj=engine)
    assert result.exit_code == 1
    assert "b: failed, 11 steps" in result.stdout and "singular at t = 0.1 s" in result.stdout
    assert json.loads((tmp_path / "r" / "b.summary.json").read_text())["status"] == "failed"
    assert (tmp_path / "r" / "a.xlsx").is_file()


def test_run_input_error_exits_2_with_sorted_diagnostics(tmp_path: Path) -> None:
    error = InputError(
        [
            Diagnostic("a.case.yaml", 9, 3, "analysis.end", "expected a time, got '2 m'"),
            Diagnostic(
                "a.case.yaml",
                4,
                5,
                "joints.hinge.bodies[1]",
                "unknown body 'grund'",
                hint="did you mean 'ground'?",
            ),
        ]
    )
    engine = fake_engine({"a.case.yaml": error})
    result = runner.invoke(app, ["run", *case_files(tmp_path, "a.case.yaml")], obj=engine)
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [
        "a.case.yaml:4:5: error: joints.hinge.bodies[1]: unknown body 'grund'",
        "a.case.yaml:4:5: hint: did you mean 'ground'?",
        "a.case.yaml:9:3: error: analysis.end: expected a time, got '2 m'",
    ]
    assert "Traceback" not in result.output


def test_internal_error_is_one_line_exit_1(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    engine = fake_engine({"a.case.yaml": ZeroDivisionError("float division by zero")})
    monkeypatch.delenv("LOADS_DEBUG", raising=False)
    result = runner.invoke(app, ["run", *case_files(tmp_path, "a.case.yaml")], obj=engine)
    assert result.exit_code == 1
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("loads: internal error: ZeroDivisionError")
    assert "report" in lines[0] and "Traceback" not in result.output
    monkeypatch.setenv("LOADS_DEBUG", "1")
    debug = runner.invoke(app, ["run", *case_files(tmp_path, "a.case.yaml")], obj=engine)
    assert isinstance(debug.exception, ZeroDivisionError)


def test_run_jobs_in_parallel_keeps_input_order(tmp_path: Path) -> None:
    names = [f"c{i}.case.yaml" for i in range(4)]
    engine = fake_engine({n: [outcome(n.split(".")[0])] for n in names})
    result = runner.invoke(
        app,
        ["run", *case_files(tmp_path, *names), "-o", str(tmp_path / "r"), "--jobs", "2"],
        obj=engine,
    )
    assert result.exit_code == 0, result.output
    assert [line.split(":")[0] for line in result.stdout.splitlines()] == ["c0", "c1", "c2", "c3"]
    assert len(list((tmp_path / "r").glob("*.summary.json"))) == 4


def test_missing_file_and_usage_errors_exit_2(tmp_path: Path) -> None:
    for command in ("run", "validate"):
        result = runner.invoke(app, [command, str(tmp_path / "nope.case.yaml")])
        assert result.exit_code == 2
        assert result.stderr.strip() == f"loads: error: {tmp_path / 'nope.case.yaml'}: no such file"
    assert runner.invoke(app, ["run"]).exit_code == 2
    assert runner.invoke(app, ["run", "--jobs", "0", "x"]).exit_code == 2
    assert runner.invoke(app, ["frobnicate"]).exit_code == 2


def test_validate_prints_diagnostics_sorted_and_ok(tmp_path: Path) -> None:
    good, bad = case_files(tmp_path, "good.case.yaml", "bad.case.yaml")
    found = {
        bad: [
            Diagnostic(
                "bad.case.yaml", 12, 1, "", "unknown key 'reqests'", hint="did you mean 'requests'?"
            ),
            Diagnostic("bad.mech.yaml", 3, 7, "bodies.door.mass", "expected a mass, got '2 m'"),
        ],
        good: [Diagnostic("good.case.yaml", 2, 1, "loads", "no loads listed", severity="warning")],
    }
    engine = Engine(check_file=lambda path: found[str(path)])
    result = runner.invoke(app, ["validate", good, bad], obj=engine)
    assert result.exit_code == 2
    assert result.stdout.splitlines() == [
        "bad.case.yaml:12:1: error: unknown key 'reqests'",
        "bad.case.yaml:12:1: hint: did you mean 'requests'?",
        "bad.mech.yaml:3:7: error: bodies.door.mass: expected a mass, got '2 m'",
        "good.case.yaml:2:1: warning: loads: no loads listed",
        f"{good}: ok",
    ]
    assert runner.invoke(app, ["validate", good], obj=engine).exit_code == 0


def test_validate_real_bad_file(tmp_path: Path) -> None:
    loader = pytest.importorskip("loadcases.inputs.loader")
    if not hasattr(loader, "validate_files"):
        pytest.skip("loadcases.inputs.loader.validate_files not written yet")
    bad = tmp_path / "bad.case.yaml"
    bad.write_text(
        "case: bad\nmechanism:\n  bodies:\n    door: {mass: 2 m}\n"
        "analysis: {type: kinematic, end: 1, step: 0.1}\n"
    )
    result = runner.invoke(app, ["validate", str(bad)])
    assert result.exit_code == 2, result.output
    assert re.search(r"bad\.case\.yaml:\d+:\d+: error: ", result.stdout), result.stdout
    assert "Traceback" not in result.output


def test_schema_prints_valid_json() -> None:
    schema = pytest.importorskip("loadcases.schema")
    if not hasattr(schema, "json_schema"):
        pytest.skip("loadcases.schema.json_schema not written yet")
    result = runner.invoke(app, ["schema"])
    assert result.exit_code == 0, result.output
    assert isinstance(json.loads(result.stdout), dict)


def test_envelope_to_stdout_and_workbook(tmp_path: Path) -> None:
    write_results(outcome("a"), tmp_path / "r", version="0")
    write_results(outcome("sub/b", scale=3.0), tmp_path / "r", version="0")
    result = runner.invoke(app, ["envelope", str(tmp_path / "r")])
    assert result.exit_code == 0, result.output
    lines = [line.split(",")[:7] for line in result.stdout.splitlines()]
    assert lines == [
        ["column", "max", "max_run", "max_time", "min", "min_run", "min_time"],
        ["pivot_force.fx", "3.0", "sub/b", "0.0", "-6.0", "sub/b", "0.1"],
    ]
    book_path = tmp_path / "env.xlsx"
    result = runner.invoke(app, ["envelope", str(tmp_path / "r"), "-o", str(book_path)])
    assert result.exit_code == 0, result.output
    rows = list(openpyxl.load_workbook(book_path)["Envelope"].iter_rows(values_only=True))
    assert rows[1][:7] == ("pivot_force.fx", 3.0, "sub/b", 0.0, -6.0, "sub/b", 0.1)


def test_envelope_errors_exit_2(tmp_path: Path) -> None:
    assert runner.invoke(app, ["envelope", str(tmp_path / "none")]).exit_code == 2
    result = runner.invoke(app, ["envelope", str(tmp_path)])
    assert result.exit_code == 2 and "no results" in result.stderr
    assert runner.invoke(app, ["envelope", str(tmp_path), "-o", "x.txt"]).exit_code == 2


def test_bench_runs_suite_main_or_reports_missing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(cli_app, "_find_bench_suite", lambda: None)
    result = runner.invoke(app, ["bench"])
    assert result.exit_code == 2 and "benchmarks/suite.py not found" in result.stderr
    suite = tmp_path / "benchmarks" / "suite.py"
    suite.parent.mkdir()
    suite.write_text("def main(argv):\n    print('suite', argv)\n    return 0\n")
    monkeypatch.setattr(cli_app, "_find_bench_suite", lambda: suite)
    result = runner.invoke(app, ["bench", "--quick"])
    assert result.exit_code == 0 and "suite ['--quick']" in result.stdout
    result = runner.invoke(app, ["bench", "--kinds", "--quick"])
    assert result.exit_code == 0 and "suite ['--quick', '--kinds']" in result.stdout
    for module, flag, code in (
        ("door_set", "--door", 1),
        ("campaign", "--campaign", 0),
        ("scaling", "--scaling", 0),
    ):
        (suite.parent / f"{module}.py").write_text(
            f"def main(argv):\n    print('{flag[2:]}', argv)\n    return {code}\n"
        )
        result = runner.invoke(app, ["bench", flag])
        assert result.exit_code == code and f"{flag[2:]} []" in result.stdout


def test_bench_suite_in_a_package_may_use_relative_imports(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    package = tmp_path / "benchmarks"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "models.py").write_text("CODE = 3\n")
    (package / "suite.py").write_text(
        "from .models import CODE\n\ndef main(argv):\n    return CODE\n"
    )
    for name in [n for n in sys.modules if n == "benchmarks" or n.startswith("benchmarks.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setattr(cli_app, "_find_bench_suite", lambda: package / "suite.py")
    try:
        result = runner.invoke(app, ["bench"])
    finally:
        for name in [n for n in sys.modules if n == "benchmarks" or n.startswith("benchmarks.")]:
            del sys.modules[name]
    assert result.exit_code == 3, result.output
    assert str(tmp_path) not in sys.path


def test_console_entry_point_is_main() -> None:
    module = importlib.import_module("cli.app")
    assert callable(module.main) and module.app is app


def test_progress_bar_draws_and_erases() -> None:
    stream = io.StringIO()
    bar = ProgressBar("a.case.yaml", stream=stream)
    bar(0.5, 1.0)
    bar(0.6, 1.0)  # within the redraw interval: skipped
    bar(1.0, 1.0)  # the end is always drawn
    drawn = stream.getvalue().split("\r")[1:]
    assert len(drawn) == 2
    assert drawn[0].startswith("a.case.yaml [" + "#" * 15 + "." * 15 + "]  50%  t = 0.5 / 1 s")
    assert "100%" in drawn[1]
    bar.close()
    assert stream.getvalue().endswith("\r" + " " * len(drawn[0].rstrip()) + "\r")


def test_progress_bar_names_the_stage_of_a_further_solve() -> None:
    """After the run, the bar draws its accuracy estimate's solves (the companion, a
    tighter run) named after the file's, from 0 % again, not a bar stuck at 100 %."""
    stream = io.StringIO()
    bar = ProgressBar("a.case.yaml", stream=stream)
    bar(1.0, 1.0)
    assert bar.staged("accuracy: companion run") is bar
    bar(1.0, 2.0)  # drawn at once: a new stage
    drawn = stream.getvalue().split("\r")[1:]
    assert drawn[0].startswith("a.case.yaml [" + "#" * 30 + "] 100%")
    assert drawn[1].startswith(
        "a.case.yaml (accuracy: companion run) [" + "#" * 15 + "." * 15 + "]  50%  t = 1 / 2 s"
    )


def test_set_progress_counts_every_failure_and_draws_the_end() -> None:
    """The set's progress line shares the bar's redrawing: failures are counted on every
    call, the line is redrawn only after the interval or at the end."""
    stream = io.StringIO()
    progress = SetProgress("s.set.yaml", stream=stream)
    failed, ok = types.SimpleNamespace(ok=False), types.SimpleNamespace(ok=True)
    progress(failed, 1, 3)
    progress(failed, 2, 3)  # within the redraw interval: counted, not drawn
    progress(ok, 3, 3)
    drawn = stream.getvalue().split("\r")[1:]
    assert [line.split(", ~")[0] for line in drawn] == [
        "s.set.yaml: 1/3 runs, 1 failed",
        "s.set.yaml: 3/3 runs, 2 failed",
    ]
    progress.close()
    assert stream.getvalue().endswith("\r" + " " * max(map(len, drawn)) + "\r")


def test_set_progress_says_which_part_of_the_report_it_writes(tmp_path: Path) -> None:
    """`run_set(on_report=...)` is called for each part; the line names it."""
    from loadcases.sets.campaign import run_set
    from tests.loadcases.set_fixtures import write_inputs

    stream = io.StringIO()
    progress = SetProgress("crank.set.yaml", stream=stream)
    folder = write_inputs(tmp_path)
    run_set(folder / "crank.set.yaml", output_dir=tmp_path / "out", on_report=progress.report)
    drawn = [line.strip() for line in stream.getvalue().split("\r")[1:]]
    assert drawn[0] == "crank.set.yaml: writing the report: envelope (0 s)"
    assert any("workbook: time histories 6/6" in line for line in drawn)
    assert drawn[-1].startswith("crank.set.yaml: writing the report: envelope plots (")


def test_schema_lets_accuracy_off_through() -> None:
    """`analysis.accuracy: off` is a string as well as the const `off`: under `oneOf`
    (exactly one branch) a schema validator refused it (an editor marked every
    `accuracy: off` as an error); the forms are `anyOf` (the engine tells them apart)."""
    result = runner.invoke(app, ["schema"])
    accuracy = json.loads(result.stdout)["$defs"]["Analysis"]["properties"]["accuracy"]
    forms = accuracy["anyOf"][0]
    assert "oneOf" not in forms
    assert {"const": "off", "type": "string"} in forms["anyOf"]
    assert {"$ref": "#/$defs/AccuracyTarget"} in forms["anyOf"]
