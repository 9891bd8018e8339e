"""Assembly branches: a landing-gear side-brace (trunnion strut, two brace links, a knee)
drawn with its knee 10 mm off straight. Assembled from `initial: {trunnion: {value: 90
deg}}` it must stay on the drawn branch (the knee on the side it is drawn on; before, the
assembly folded it the mirror way without a word), a `guess:` picks the other branch, a
guess nothing meets is a warning (or with `branches: {on_change: error}` a failure), and a
kinematic or quasi-static run that jumps to the mirror assembly says so. References: the
closed form of the brace (two circles' intersection) for the assembled angles."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from cli.app import app
from loadcases.run import run_file

TOP = np.array([0.9, -0.1])  # brace_top, m
KNEE = np.array([0.45, -0.39])  # drawn knee: 10 mm above the straight brace
FOOT = np.array([0.0, -0.7])  # brace_leg, on the strut

CASE = """\
case: {name}
units: {{length: mm, angle: deg}}
mechanism:
  plane: xy
  gravity: [0, -9.81, 0]
  bodies:
    leg:   {{mass: 50, cm: [0, -500, 0], inertia: [2, 2, 4]}}
    upper: {{mass: 5, cm: [675, -245, 0], inertia: [0.05, 0.05, 0.1]}}
    lower: {{mass: 5, cm: [225, -545, 0], inertia: [0.05, 0.05, 0.1]}}
  joints:
    trunnion:  {{type: revolute, bodies: [leg, ground], at: [0, 0, 0], axis: [0, 0, 1]}}
    brace_top: {{type: revolute, bodies: [upper, ground], at: [900, -100, 0], axis: [0, 0, 1]}}
    knee:      {{type: revolute, bodies: [lower, upper], at: [450, -390, 0], axis: [0, 0, 1]}}
    brace_leg: {{type: revolute, bodies: [lower, leg], at: [0, -700, 0], axis: [0, 0, 1]}}
{body}
requests:
  knee: {{joint: knee, quantity: angle}}
  brace_top: {{joint: brace_top, quantity: angle}}
"""
FREE_FALL = "analysis: {type: dynamic, end: 0.01, step: 0.01, accuracy: off}"


def _write(tmp_path: Path, name: str, body: str) -> Path:
    path = tmp_path / f"{name}.case.yaml"
    path.write_text(CASE.format(name=name, body=body), encoding="utf-8")
    return path


def _solve(tmp_path: Path, name: str, body: str):
    (outcome,) = run_file(_write(tmp_path, name, body), output_dir=tmp_path / "out")
    return outcome.solution


def _branch_warnings(solution) -> list[str]:
    return [w for w in solution.warnings if "assembly branch" in w]


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def _closed_form(trunnion: float, side: float) -> tuple[float, float]:
    """(knee, brace_top) angles (rad) of the brace with the strut turned by `trunnion`:
    the knee where the circles about brace_top and the foot meet, on the `side` (+1: the
    drawn one) of the line from brace_top to the foot."""
    c, s = math.cos(trunnion), math.sin(trunnion)
    foot = np.array([c * FOOT[0] - s * FOOT[1], s * FOOT[0] + c * FOOT[1]])
    upper, lower = np.linalg.norm(KNEE - TOP), np.linalg.norm(KNEE - FOOT)
    span = foot - TOP
    d = np.linalg.norm(span)
    along = (upper**2 - lower**2 + d**2) / (2 * d)
    normal = np.array([-span[1], span[0]]) / d
    a, b = FOOT - TOP, KNEE - TOP
    drawn_side = math.copysign(1.0, float(a[0] * b[1] - a[1] * b[0]))
    knee = TOP + along * span / d + side * drawn_side * math.sqrt(upper**2 - along**2) * normal

    def turn(a: np.ndarray, b: np.ndarray) -> float:
        return math.atan2(a[0] * b[1] - a[1] * b[0], a @ b)

    top_turn = turn(KNEE - TOP, knee - TOP)
    lower_turn = turn(KNEE - FOOT, knee - foot)
    return _wrap(lower_turn - top_turn), top_turn


def test_the_assembly_keeps_the_drawn_branch(tmp_path: Path) -> None:
    """trunnion 90 deg: knee and brace_top within 1e-8 rad of the closed form on the drawn
    side (knee +154.4 deg; the mirror one, -157.9 deg, is what the assembly gave before),
    with no branch warning."""
    sol = _solve(tmp_path, "drawn", f"initial:\n  trunnion: {{value: 90 deg}}\n{FREE_FALL}")
    knee, top = _closed_form(math.pi / 2, +1.0)
    assert math.degrees(knee) == pytest.approx(154.4, abs=0.1)
    assert sol.channels["knee.value"][0] == pytest.approx(knee, abs=1e-8)
    assert sol.channels["brace_top.value"][0] == pytest.approx(top, abs=1e-8)
    assert _branch_warnings(sol) == []


def test_a_guess_chooses_the_other_branch(tmp_path: Path) -> None:
    """`knee: {guess: -150 deg}` assembles the mirror brace (closed form, 1e-8 rad), the
    given trunnion angle kept exactly; silent: -157.9 deg is within 30 deg of the guess."""
    body = f"initial:\n  trunnion: {{value: 90 deg}}\n  knee: {{guess: -150 deg}}\n{FREE_FALL}"
    sol = _solve(tmp_path, "guess", body)
    knee, top = _closed_form(math.pi / 2, -1.0)
    assert sol.channels["knee.value"][0] == pytest.approx(knee, abs=1e-8)
    assert sol.channels["brace_top.value"][0] == pytest.approx(top, abs=1e-8)
    assert _branch_warnings(sol) == []
    assert not any("changed from" in w for w in sol.warnings)  # the given value is kept


def test_a_guess_nothing_meets_is_a_warning_or_with_on_change_error_a_failure(
    tmp_path: Path,
) -> None:
    """A knee guess of 60 deg: the nearest assembly is 94 deg away (more than the default 30
    deg): the summary names the joint, its guess, its assembled value and the time. With
    `branches: {angle: 100 deg}` it is silent; with `on_change: error` the run fails."""
    initial = "initial:\n  trunnion: {value: 90 deg}\n  knee: {guess: 60 deg}\n"
    (warning,) = _branch_warnings(_solve(tmp_path, "far", initial + FREE_FALL))
    assert warning.startswith(
        "assembly branch changed at t = 0 s: joint 'knee' guess 60 deg, assembled 154.4"
    )
    wide = _solve(tmp_path, "wide", initial + "branches: {angle: 100 deg}\n" + FREE_FALL)
    assert _branch_warnings(wide) == []
    failed = _solve(tmp_path, "strict", initial + "branches: {on_change: error}\n" + FREE_FALL)
    assert failed.status == "failed"
    assert failed.result.code == "branch_changed"
    assert "joint 'knee' guess 60 deg" in failed.message


def _driven(analysis: str, step: float, on_change: str = "warn") -> str:
    return (
        'motions:\n  swing: {joint: trunnion, value: "t*90*deg"}\n'
        f"branches: {{on_change: {on_change}}}\n"
        f"analysis: {{type: {analysis}, end: 1, step: {step}}}"
    )


@pytest.mark.parametrize(
    ("analysis", "step", "time"), [("kinematic", 0.5, 0.5), ("quasi-static", 0.1, 0.1)]
)
def test_a_run_that_jumps_to_the_mirror_branch_says_where(
    tmp_path: Path, analysis: str, step: float, time: float
) -> None:
    """Driven from the near-straight drawing, the kinematic run's first 45 deg step and the
    quasi-static run's first equilibrium land on the mirror brace (knee negative): the
    constraints' orientation changed between two rows; the warning names the knee first
    (it moved most) and the time of the row after the jump."""
    sol = _solve(tmp_path, analysis.replace("-", ""), _driven(analysis, step))
    assert sol.ok
    assert sol.channels["knee.value"][-1] == pytest.approx(_closed_form(math.pi / 2, -1.0)[0])
    (warning,) = _branch_warnings(sol)
    assert warning.startswith(f"assembly branch changed at t = {time:g} s: joint 'knee' ")
    assert "orientation changed sign" in warning


def test_a_run_on_its_branch_is_silent_and_an_error_keeps_the_rows(tmp_path: Path) -> None:
    """With 0.1 s rows the kinematic run follows the drawn branch to the closed form (knee
    +154.4 deg at 90 deg, 1e-6 rad) without a branch warning; with 0.5 s rows and
    `on_change: error` it fails and keeps its three rows; `loads run` exits 1."""
    sol = _solve(tmp_path, "fine", _driven("kinematic", 0.1))
    assert sol.channels["knee.value"][-1] == pytest.approx(_closed_form(math.pi / 2, 1.0)[0])
    assert _branch_warnings(sol) == []
    path = _write(tmp_path, "coarse", _driven("kinematic", 0.5, "error"))
    (outcome,) = run_file(path, output_dir=tmp_path / "out")
    assert outcome.solution.status == "failed"
    assert len(outcome.solution.time) == 3
    assert outcome.solution.message.startswith("assembly branch changed at t = 0.5 s")
    result = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "cli")])
    assert result.exit_code == 1, result.output
    assert "assembly branch changed at t = 0.5 s" in result.output


def test_a_guess_on_a_body_is_an_input_error(tmp_path: Path) -> None:
    from loadcases.foundation.diagnostics import InputError

    body = f"initial:\n  leg: {{guess: 10 deg}}\n{FREE_FALL}"
    with pytest.raises(InputError) as caught:
        run_file(_write(tmp_path, "body-guess", body), output_dir=tmp_path / "out")
    assert [d.message for d in caught.value.diagnostics] == [
        "'leg' is a body: give 'omega' and/or 'velocity'"
    ]


LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library"


@pytest.mark.parametrize(
    "case",
    [
        "verification/slider_crank.case.yaml",
        "verification/fourbar_quasistatic.case.yaml",
        "verification/hard/iftomm_a02_fourbar_planar.case.yaml",
        "door/opened.case.yaml",
    ],
)
def test_library_cases_that_assemble_normally_are_silent(tmp_path: Path, case: str) -> None:
    """Slider-crank, four-bars and the door opened to 110 deg latch / 151 deg handle (its
    linkage 55-110 deg from the drawing, on the drawn branch): no branch warning."""
    for outcome in run_file(LIBRARY / case, output_dir=tmp_path / "out"):
        assert outcome.solution.ok
        assert _branch_warnings(outcome.solution) == []


def test_loads_draw_shows_the_drawing_under_another_branch(tmp_path: Path) -> None:
    """`loads draw` of the mirror assembly (guess far off: a branch warning) prints the
    warning and draws the drawn geometry as a ghost: the grey crosses at the drawn joints
    (projected on xy, to 1e-12 m), a grey dashed trace on the 3-D page; a run starting at
    its drawing gets no ghost."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from loadcases.draw.render import _draw_ghost
    from loadcases.draw.scene import frame_traces, scene_of
    from loadcases.draw.trajectory import trajectory_of_file

    body = f"initial:\n  trunnion: {{value: 90 deg}}\n  knee: {{guess: 60 deg}}\n{FREE_FALL}"
    path = _write(tmp_path, "ghost", body)
    result = CliRunner().invoke(app, ["draw", str(path), "-o", str(tmp_path / "pics")])
    assert result.exit_code == 0, result.output
    assert "warning: assembly branch changed at t = 0 s: joint 'knee' guess 60 deg" in (
        result.output
    )
    assert len(list((tmp_path / "pics").glob("ghost-t*.png"))) >= 1
    traj = trajectory_of_file(path)
    fig, ax = plt.subplots()
    try:
        lines = _draw_ghost(ax, traj, np.eye(3)[:2])
        crosses = sorted(tuple(line.get_xydata()[0]) for line in lines if line.get_marker() == "x")
        drawn = sorted(tuple(traj.drawn(m)[:2]) for m in traj.skeleton.joints.values())
        assert np.allclose(crosses, drawn, atol=1e-12)
        at_drawing = trajectory_of_file(_write(tmp_path, "still", FREE_FALL))
        assert _draw_ghost(ax, at_drawing, np.eye(3)[:2]) == []
    finally:
        plt.close(fig)
    names = [t["name"] for t in frame_traces(traj, scene_of(traj), 0)]  # the 3-D page
    assert names[0] == "as drawn"
    assert "as drawn" not in [t["name"] for t in frame_traces(at_drawing, scene_of(at_drawing), 0)]


PARALLELOGRAM = """\
case: {name}
units: {{length: mm, angle: deg}}
mechanism:
  plane: xy
  bodies:
    crank:  {{mass: 1, cm: [0, 250, 0], inertia: [0.02, 0.02, 0.03]}}
    rocker: {{mass: 1, cm: [1000, 250, 0], inertia: [0.02, 0.02, 0.03]}}
    coupler: {{mass: 1, cm: [500, 500, 0], inertia: [0.02, 0.08, 0.09]}}
  joints:
    a: {{type: revolute, bodies: [crank, ground], at: [0, 0, 0], axis: [0, 0, 1]}}
    b: {{type: revolute, bodies: [coupler, crank], at: [0, 500, 0], axis: [0, 0, 1]}}
    c: {{type: revolute, bodies: [coupler, rocker], at: [1000, 500, 0], axis: [0, 0, 1]}}
    d: {{type: revolute, bodies: [rocker, ground], at: [1000, 0, 0], axis: [0, 0, 1]}}
initial:
  a: {{value: {angle} deg}}
{branches}
analysis: {{type: dynamic, end: 0.01, step: 0.01, accuracy: off}}
requests:
  d: {{joint: d, quantity: angle}}
"""


@pytest.mark.parametrize("angle", [60, 120])
def test_a_parallelogram_past_its_bifurcation(tmp_path: Path, angle: int) -> None:
    """A parallelogram four-bar (cranks 0.5 m, coupler and ground 1 m) drawn with upright
    cranks, its crank given 60 or 120 deg. At 90 deg all four links align: a bifurcation,
    where it may go on as a parallelogram or fold into an antiparallelogram (at 120 deg
    the rocker at 79.79 deg: what the assembly gave before). It stays a parallelogram
    (closed form: rocker angle = crank angle, 1e-8 rad); 60 deg is silent, 120 deg warns
    that the way passed a singular position, naming the coupler's and rocker's joints."""
    path = tmp_path / f"pg{angle}.case.yaml"
    path.write_text(
        PARALLELOGRAM.format(name=f"pg{angle}", angle=angle, branches=""), encoding="utf-8"
    )
    (outcome,) = run_file(path, output_dir=tmp_path / "out")
    sol = outcome.solution
    assert sol.channels["d.value"][0] == pytest.approx(math.radians(angle), abs=1e-8)
    warnings = _branch_warnings(sol)
    if angle < 90:
        assert warnings == []
    else:
        (warning,) = warnings
        assert warning.startswith(
            "assembly branch changed at t = 0 s: joint 'c' drawn 0 deg, assembled -120 deg; "
            "joint 'd' drawn 0 deg, assembled 120 deg; joint 'b' drawn 0 deg, assembled -120 deg"
        )
        assert "toggle or a bifurcation" in warning


def test_a_guess_that_does_nothing_is_a_warning(tmp_path: Path) -> None:
    """A guess of a joint whose value is given (or that a motion drives) is a warning at
    its key; a guess of a joint the assembly solves for is not."""
    from loadcases.inputs.loader import validate_files

    idle = _write(
        tmp_path, "idle", f"initial:\n  trunnion: {{value: 90 deg, guess: 80 deg}}\n{FREE_FALL}"
    )
    useful = _write(
        tmp_path,
        "useful",
        f"initial:\n  trunnion: {{value: 90 deg}}\n  knee: {{guess: 150 deg}}\n{FREE_FALL}",
    )
    found = [f"{d.severity} {d.key}: {d.message}" for d in validate_files([idle, useful])]
    assert found == [
        "warning initial.trunnion.guess: the guess of joint 'trunnion' does nothing: its "
        "'value' sets its coordinate"
    ]
