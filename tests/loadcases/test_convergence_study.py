"""The convergence study of `loads converge` (issue 37 item 1) on a Craig-Bampton
cantilever whose answers are known.

References: Euler-Bernoulli cantilever frequencies f_i = (beta_i L)^2 / (2 pi) *
sqrt(E I / (rho A L^4)), beta_1 L = 1.875104, beta_2 L = 4.694091 (Blevins, Formulas for
natural frequency and mode shape, table 8-1); the static tip deflection P L^3 / (3 E I).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

from cli.converge_cmd import tolerance_fraction
from loadcases.foundation.diagnostics import InputError
from loadcases.studies.convergence import converged_index, run_study
from loadcases.studies.convergence_files import convergence_csv_text, write_convergence_files

E, RHO, WIDTH, HEIGHT, LENGTH = 70e9, 2700.0, 0.03, 0.01, 1.0
EI_SOFT = E * WIDTH * HEIGHT**3 / 12.0  # bending in z (about y), N*m^2

CASE = """\
case: cantilever
mechanism:
  units: {length: mm}
  parameters: {n_fi: 2}
  bodies:
    beam:
      flexible:
        beam:
          start: [0, 0, 0]
          end: [1000, 0, 0]
          section: {width: 30, height: 10, shear: false}
          material: {E: 70 GPa, nu: 0.33, rho: 2700 kg/m^3}
          elements: 16
          y_axis: [0, 1, 0]
        interface: {root: [0, 0, 0], tip: [1000, 0, 0]}
        fixed_interface_modes: n_fi
  joints:
    clamp: {type: fixed, bodies: [beam, ground], at: [0, 0, 0]}
  forces:
    load: {type: force, point: beam.tip, value: [0, 0, 2]}
effects: {gravity: false}
analysis: {type: ANALYSIS}
requests:
  tip: {point: beam.tip, quantity: position}
  clamp_force: {joint: clamp, quantity: force}
"""


def _case(tmp_path: Path, analysis: str) -> Path:
    path = tmp_path / f"{analysis}.case.yaml"
    path.write_text(CASE.replace("ANALYSIS", analysis), "utf-8")
    return path


def _euler_bernoulli(beta_l: float) -> float:
    return beta_l**2 / (2 * math.pi) * math.sqrt(EI_SOFT / (RHO * WIDTH * HEIGHT * LENGTH**4))


def test_verdict_is_the_first_value_from_which_the_rest_stays_within_tolerance() -> None:
    """The seed's figure 3.2.2-3 pattern: 6 % off with 2 modes, under 1 % from 10 on."""
    peaks = [1.06, 1.03, 1.012, 1.008, 1.0005, 1.0]  # at 2, 3, 4, 5, 10, 30 modes
    assert converged_index(peaks, 0.01) == 3  # 1.008 .. 1.0: spread 0.8 % of 1.0
    assert converged_index(peaks, 0.001) == 4
    assert converged_index(peaks, 1e-5) is None  # only the last value agrees with itself
    assert converged_index([1.0, 1.2, 1.0, 1.0], 0.01) == 2  # a later excursion resets it
    assert converged_index([0.0, 0.0], 0.01) == 0  # exact zeros agree
    assert converged_index([1.0, math.nan, 1.0], 0.5) is None
    assert converged_index([1.0, math.nan, 1.0, 1.0], 0.5) == 2  # no verdict across a failure


def test_mode_study_converges_to_euler_bernoulli(tmp_path: Path) -> None:
    """Craig-Bampton frequencies approach the beam's from above as fixed-interface modes
    are added: the first soft bending mode (mode 1) is 0.47 % high with none (the constraint
    modes alone: a Rayleigh-Ritz value) and converges at 1 within 0.1 %; the second soft
    bending (mode 3) is 58 % high with none and converges at 4. The converged values match
    Euler-Bernoulli within 2e-4 (measured 1e-5 and 1.5e-4: the 16-element mesh and the
    rotary inertia of its consistent mass)."""
    study = run_study(
        _case(tmp_path, "modes"),
        parameter="n_fi",
        texts=["0", "1", "2", "4", "8", "16"],
        tolerance=0.001,
    )
    modes = {q.name: q for q in study.quantities}
    first, second = modes["mode 1"], modes["mode 3"]
    f1, f2 = _euler_bernoulli(1.875104), _euler_bernoulli(4.694091)
    assert first.values[0] / f1 - 1.0 == pytest.approx(4.7e-3, abs=5e-4)
    assert second.values[0] / f2 - 1.0 > 0.5
    assert first.converged_at == 1  # n_fi = 1
    assert second.converged_at == 3  # n_fi = 4
    assert first.values[-1] == pytest.approx(f1, rel=2e-4)
    assert second.values[-1] == pytest.approx(f2, rel=2e-4)
    assert all(b <= a * (1 + 1e-12) for a, b in zip(first.values, first.values[1:]))
    assert modes["mode 7"].converged_at is None  # absent below 1 mode, moving above


def test_static_tip_load_is_exact_at_every_mode_count(tmp_path: Path) -> None:
    """A load at an interface node: the constraint modes are the static condensation, so
    the tip deflection is P L^3 / (3 E I) with no fixed-interface mode at all (measured
    1e-4: the floating frame's second-order geometry) and the study says converged at the
    first value; the files carry every value and the verdict."""
    study = run_study(
        _case(tmp_path, "static"),
        parameter="n_fi",
        texts=["0", "3"],
        tolerance=0.001,
        columns=["tip.*", "clamp_force.f?"],
    )
    assert {q.name.split(".")[0] for q in study.quantities} == {"tip", "clamp_force"}
    assert not any(q.name.startswith("clamp_force.t") for q in study.quantities)
    quantities = {q.name: q for q in study.quantities}
    bend = quantities["tip.z max"]
    assert bend.values[0] == pytest.approx(2.0 * LENGTH**3 / (3 * EI_SOFT), rel=1e-3)
    assert bend.converged_at == 0
    assert quantities["clamp_force.fz max"].values == pytest.approx((-2.0, -2.0), rel=1e-9)
    assert quantities["clamp_force.fy max"].noise  # no load across: round-off
    table, diagram = write_convergence_files(study, tmp_path / "out")
    rows = list(csv.reader(table.open(encoding="utf-8")))
    assert rows[0][:4] == ["quantity", "unit", "n_fi=0 [unit]", "n_fi=3 [unit]"]
    assert rows[0][4] == "converged_at [n_fi]"
    row = next(r for r in rows if r[0] == "tip.z max")
    assert row[1] == "m" and row[4] == "0" and row[6] == ""
    assert rows[-2][0] == "cost.steps" and rows[-1][0] == "cost.cpu_seconds"
    assert diagram.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bad_study_input_names_the_problem(tmp_path: Path) -> None:
    path = _case(tmp_path, "static")
    with pytest.raises(InputError, match="increase"):
        run_study(path, parameter="n_fi", texts=["4", "2"], tolerance=0.01)
    with pytest.raises(InputError, match="no parameter 'n_modes'"):
        run_study(path, parameter="n_modes", texts=["2", "4"], tolerance=0.01)
    with pytest.raises(InputError, match=r"columns 'tip\.w': matches no result"):
        run_study(path, parameter="n_fi", texts=["0", "1"], tolerance=0.01, columns=["tip.w"])
    with pytest.raises(InputError, match="at least two"):
        run_study(path, parameter="n_fi", texts=["2"], tolerance=0.01)
    assert tolerance_fraction("1 %") == pytest.approx(0.01)
    assert tolerance_fraction("0.02") == pytest.approx(0.02)
    with pytest.raises(ValueError):
        tolerance_fraction("150 %")


def test_command_prints_the_verdicts_and_writes_the_files(tmp_path: Path) -> None:
    """`loads converge`: the table printed with a verdict per quantity, the two files
    written, exit 0; an unreadable tolerance and an unknown parameter exit 2."""
    from typer.testing import CliRunner

    from cli.app import app

    runner = CliRunner()
    path, out = _case(tmp_path, "static"), tmp_path / "study"
    base = ["converge", str(path), "--parameter", "n_fi", "-o", str(out)]
    ok = runner.invoke(app, [*base, "--values", "0,2", "-c", "tip.z"])
    assert ok.exit_code == 0, ok.output
    assert "tip.z max" in ok.output and "converged at n_fi = 0" in ok.output
    assert (out / "cantilever.convergence.csv").is_file()
    assert (out / "cantilever.convergence.png").is_file()
    bad = runner.invoke(app, [*base, "--values", "0,2", "--tolerance", "lots"])
    assert bad.exit_code == 2 and "--tolerance lots" in bad.output
    blocked = runner.invoke(app, [*base[:4], "-o", str(path), "--values", "0,2"])
    assert blocked.exit_code == 2 and "is a file, not a folder" in blocked.output
    unknown = runner.invoke(app, ["converge", str(path), "--parameter", "n", "--values", "0,2"])
    assert unknown.exit_code == 2 and "no parameter 'n'" in unknown.output


def test_failed_runs_are_kept_and_named(tmp_path: Path) -> None:
    """A run that fails (here: at most 3 steps) gives no value (its column empty), no
    verdict across it, the failure in the table's last row; the command exits 1."""
    from typer.testing import CliRunner

    from cli.app import app

    path = tmp_path / "short.case.yaml"
    text = CASE.replace("ANALYSIS", "dynamic, end: 0.5, step: 0.01, max_steps: 3")
    path.write_text(text, "utf-8")
    study = run_study(path, parameter="n_fi", texts=["0", "1"], tolerance=0.01, columns=["tip.z"])
    assert [r.ok for r in study.runs] == [False, False] and len(study.failed) == 2
    assert all(math.isnan(v) for q in study.quantities for v in q.values)
    assert all(q.converged_at is None for q in study.quantities)
    text = convergence_csv_text(study)
    assert text.splitlines()[-1].endswith('"failed: 0, 1"')
    result = CliRunner().invoke(
        app,
        ["converge", str(path), "--parameter", "n_fi", "--values", "0,1", "-o", str(tmp_path)],
    )
    assert result.exit_code == 1 and "FAILED" in result.output
