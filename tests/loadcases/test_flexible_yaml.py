"""Flexible bodies in YAML (issue 13): `bodies: NAME: flexible:` with a beam or a grillage.

Reference: the static tip deflection of a clamped Timoshenko cantilever,
P L^3/(3 E I) + P L/(k G A), with the section given in mm and the load in N; the deformation
request and the modal coordinates are reported.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.inputs.loader import load_case
from loadcases.run import run_case

LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library"

CASE = """\
case: flexible-cantilever
mechanism:
  units: {length: mm}
  bodies:
    beam:
      flexible:
        beam:
          start: [0, 0, 0]
          end: [800, 0, 0]
          section: {width: 30, height: 10}
          material: {E: 70 GPa, nu: 0.33, rho: 2700 kg/m^3}
          elements: 8
          y_axis: [0, 1, 0]
        interface: {root: [0, 0, 0], tip: [800, 0, 0]}
        fixed_interface_modes: 6
{extra_body}
  joints:
    clamp: {type: fixed, bodies: [beam, ground], at: [0, 0, 0]}
  forces:
    load: {type: force, point: beam.tip, value: [0, 0, 5]}
analysis: {type: static}
requests:
  tip: {point: beam.tip, quantity: position}
  bend: {flexible: beam, quantity: deformation, point: beam.tip}
  modal: {flexible: beam, quantity: modes}
  clamp_force: {joint: clamp, quantity: force}
"""


def _case(tmp_path: Path, extra_body: str = "", replace: tuple[str, str] = ("", "")):
    path = tmp_path / "flex.case.yaml"
    path.write_text(CASE.replace("{extra_body}", extra_body).replace(*replace), "utf-8")
    return load_case(path)


def test_static_cantilever_from_yaml(tmp_path: Path) -> None:
    """0.8 m, 30 x 10 mm aluminium, 5 N at the tip: closed form to 0.1 % (measured 8.2e-5
    below, the floating frame's second-order geometry at a 4.9 mm deflection); the tip's
    deformation is measured from the floating (mean-axis) frame, which turns with the beam
    (0.49 mm here), and every mode is reported."""
    outcome = run_case(_case(tmp_path))
    channels = outcome.solution.channels
    E, G, width, height, L, P = 70e9, 70e9 / 2.66, 0.03, 0.01, 0.8, 5.0
    iy, area = width * height**3 / 12.0, width * height
    exact = P * L**3 / (3 * E * iy) + P * L / (5.0 / 6.0 * G * area)
    assert channels["tip.z"][0] == pytest.approx(exact, rel=1e-3)
    assert channels["bend.z"][0] != 0.0
    assert sum(1 for c in channels if c.startswith("modal.q")) == 12 + 6 - 6


def test_clamp_reaction_of_a_flexible_body(tmp_path: Path) -> None:
    """The clamp's reaction on the beam (its root node body) balances the tip load: -5 N
    along z and P x_tip about y at the root, x_tip the tip's deformed position (1e-9
    relative; x_tip is 1.5e-5 m short of L, the floating frame's second-order geometry).
    Regression: a joint reaction on a
    flexible body read the modal body's columns, where the joint has none (all zero)."""
    channels = run_case(_case(tmp_path)).solution.channels
    assert channels["clamp_force.fz"][0] == pytest.approx(-5.0, rel=1e-9)
    assert channels["clamp_force.ty"][0] == pytest.approx(5.0 * channels["tip.x"][0], rel=1e-9)
    assert abs(channels["clamp_force.fx"][0]) < 1e-9


@pytest.mark.parametrize(
    "replace, message",
    [
        (("tip: [800, 0, 0]}", "tip: [800, 5, 0]}"), "not on the beam"),
        (("fixed_interface_modes: 6", "modes: 60"), "60 modes asked"),
        (("width: 30, height: 10", "width: 30"), "width and height"),
    ],
)
def test_flexible_input_errors(tmp_path: Path, replace, message: str) -> None:
    with pytest.raises(InputError, match=message):
        run_case(_case(tmp_path, replace=replace))


def test_rigid_keys_on_a_flexible_body_are_an_error(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="mass"):
        _case(
            tmp_path,
            replace=("    beam:\n      flexible:", "    beam:\n      mass: 1\n      flexible:"),
        )


PANEL = """\
case: panel
mechanism:
  units: {length: mm}
  bodies:
    panel:
      flexible:
        grillage:
          at: [100, 0, 0]
          x: [0, 1, 0]
          y: [0, 0, 1]
          size: [1200, 800]
          thickness: 2
          material: {E: 70 GPa, nu: 0.33, rho: 2700 kg/m^3}
          mesh: [6, 4]
        interface: {hinge: [100, 0, 130], corner: [100, 1200, 800]}
        modes: 6
  joints:
    clamp: {type: fixed, bodies: [panel, ground], at: [100, 0, 130]}
analysis: {type: modes}
requests:
  corner: {point: panel.corner, quantity: position}
"""


def test_stiffening_and_linear_limit_keys(tmp_path: Path) -> None:
    """`stiffening: true` reaches the model: an axial pull of 2 kN at the tip stiffens the
    beam against the 5 N sideways (the string term; mechlib's tests check its size) by more
    than 1 %, and without the pull next to nothing (1e-4, measured 7.9e-6: a lateral load
    sets up no axial force but for the frame's turn); `linear_limit: 0.0002` warns at the
    tip's 0.49 mm from the floating frame (0.06 % of 0.8 m)."""

    def tip(pull: float, keys: str) -> tuple[float, list[str]]:
        replace = ("fixed_interface_modes: 6", f"fixed_interface_modes: 6\n{keys}")
        case = _case(tmp_path, replace=replace)
        path = tmp_path / "flex.case.yaml"
        path.write_text(path.read_text().replace("[0, 0, 5]", f"[{pull}, 0, 5]"), "utf-8")
        outcome = run_case(load_case(path))
        assert outcome.solution.ok, (case, outcome.solution.message)
        return float(outcome.solution.channels["tip.z"][0]), outcome.solution.warnings

    stiff = "        stiffening: true\n        linear_limit: 0.0002"
    plain, _ = tip(0.0, "")
    same, warnings = tip(0.0, stiff)
    assert same == pytest.approx(plain, rel=1e-4)
    assert [w for w in warnings if "limits 0.02 % of its size 0.8 m" in w]
    assert tip(2000.0, stiff)[0] < 0.99 * tip(2000.0, "")[0]


@pytest.mark.parametrize("source", ["grillage", "plate"])
def test_panel_from_yaml(tmp_path: Path, source: str) -> None:
    """A panel in the global y-z plane: its mass is rho lx ly t, its centre the panel's
    centre, its interface nodes at the given points; a modes analysis runs on it. `plate:`
    takes the grillage's keys (skipped without the extra `plate`, pyfe3d)."""
    from loadcases.build.model import build_run

    if source == "plate":
        pytest.importorskip("pyfe3d", reason="plate panels need: pip install 'loads[plate]'")
    path = tmp_path / "panel.case.yaml"
    path.write_text(PANEL.replace("grillage:", f"{source}:"), "utf-8")
    built = build_run(load_case(path))
    body = built.mechanism.bodies["panel"]
    assert body.mass == pytest.approx(2700.0 * 1.2 * 0.8 * 0.002, rel=1e-12)
    assert body.cm == pytest.approx((0.1, 0.6, 0.4), abs=1e-12)
    flexible = built.mechanism.flexible["panel"]
    positions = [flexible.node_position(int(i)) for i in flexible.component.node_ids]
    assert positions[0] == pytest.approx([0.1, 0.0, 0.13], abs=1e-12)
    assert positions[1] == pytest.approx([0.1, 1.2, 0.8], abs=1e-12)
    outcome = run_case(load_case(path))
    assert outcome.solution.ok
    assert len(outcome.solution.channels["mode.frequency"]) >= 6


def test_flexibility_off_makes_the_body_rigid(tmp_path: Path) -> None:
    """`effects: {flexibility: false}`: the cantilever does not bend (tip z ~ 0)."""
    outcome = run_case(
        _case(
            tmp_path,
            replace=(
                "analysis: {type: static}",
                "analysis: {type: static}\neffects: {flexibility: false}",
            ),
        )
    )
    channels = outcome.solution.channels
    assert abs(channels["tip.z"][0]) < 1e-12


def test_kinematic_analysis_names_the_modes_it_cannot_drive(tmp_path: Path) -> None:
    """A clamped flexible beam has no rigid freedom left, but its 12 modal coordinates
    (6 constraint + 6 fixed-interface modes) are free: the kinematic analysis is refused,
    the message names them and the way out; with the flexibility off it runs."""
    case = _case(
        tmp_path,
        replace=("analysis: {type: static}", "analysis: {type: kinematic, end: 0.1, step: 0.05}"),
    )
    with pytest.raises(InputError, match=r"has 12, 12 of them the modal coordinates .*beam \(12\)"):
        run_case(case)
    rigid = _case(
        tmp_path,
        replace=(
            "analysis: {type: static}",
            "analysis: {type: kinematic, end: 0.1, step: 0.05}\neffects: {flexibility: false}",
        ),
    )
    channels = run_case(rigid).solution.channels
    assert abs(channels["tip.x"][-1] - 0.8) < 1e-12


def test_a_joint_off_the_interface_points_is_an_input_error(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="carried by one"):
        run_case(_case(tmp_path, replace=("at: [0, 0, 0]}\n  forces", "at: [5, 0, 0]}\n  forces")))


def test_reduction_cached_by_its_inputs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A second build of the same flexible body reads the reduction from the cache (no
    Craig-Bampton, the same component to the bit); a changed input (the beam's length, the
    mode selection) reduces again."""
    from loadcases.build import flexible
    from loadcases.build.model import build_run

    monkeypatch.setenv("LOADS_CACHE_DIR", str(tmp_path / "cache"))
    calls = []

    def counted(*args, **kwargs):
        calls.append(1)
        return craig_bampton(*args, **kwargs)

    craig_bampton = flexible.craig_bampton
    monkeypatch.setattr(flexible, "craig_bampton", counted)
    first = build_run(_case(tmp_path)).mechanism.flexible["beam"].component
    second = build_run(_case(tmp_path)).mechanism.flexible["beam"].component
    assert len(calls) == 1
    assert np.array_equal(first.frequencies, second.frequencies)
    assert np.array_equal(first.invariants.I9, second.invariants.I9)
    assert first.mass == second.mass and isinstance(second.mass, float)
    build_run(_case(tmp_path, replace=("end: [800, 0, 0]", "end: [801, 0, 0]")))
    build_run(_case(tmp_path, replace=("fixed_interface_modes: 6", "fixed_interface_modes: 5")))
    assert len(calls) == 3
    assert len(list((tmp_path / "cache" / "flexible").glob("*.npz"))) == 3


@pytest.mark.parametrize("weight, strained", [(None, False), (1.0, True)])
def test_assembly_turns_a_flexible_body_rigidly(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, weight, strained: bool
) -> None:
    """The flexible pendulum (library example) assembled at 60 deg from its design position
    at 1 rad/s: the assembly reaches the angle and rate by rigid motion, its modal
    coordinates and rates stay 0 (1e-9); weighting the modes like the rigid coordinates (the
    former plain least squares) starts it strained (the regression this guards)."""
    import mechlib.solvers.assembly
    from loadcases.build.model import build_run
    from mechlib.system.system import System

    if weight is not None:
        monkeypatch.setattr(mechlib.solvers.assembly, "_MODAL_WEIGHT", weight)
    example = LIBRARY / "examples" / "flexible" / "flexible_pendulum.case.yaml"
    text = example.read_text().replace(
        "analysis:", "initial:\n  hinge: {value: 1.0472, rate: 1}\nanalysis:"
    )
    path = tmp_path / "pendulum.case.yaml"
    path.write_text(text)
    built = build_run(load_case(path))
    system = System(built.mechanism)
    start = mechlib.solvers.assembly.assemble(system, 0.0, built.initial)
    modal = slice(system.nq - system.nz, system.nq)
    deformed = max(np.abs(start.q[modal]).max(), np.abs(start.qd[modal]).max())
    assert (deformed > 1e-6) == strained, deformed
    assert deformed < 1e-9 or strained
    assert system.measure("hinge", "angle").value(system.kin(start.q, None, 0.0)) == (
        pytest.approx(1.0472, abs=1e-9)
    )


def test_a_plate_has_no_stiffening(tmp_path: Path) -> None:
    """`stiffening:` needs beam elements: a plate panel's is refused at its key."""
    pytest.importorskip("pyfe3d", reason="plate panels need the extra: pip install 'loads[plate]'")
    path = tmp_path / "plate.case.yaml"
    stiff = PANEL.replace("grillage:", "plate:").replace(
        "modes: 6", "modes: 6\n        stiffening: true"
    )
    path.write_text(stiff, "utf-8")
    with pytest.raises(InputError, match="a plate no beam elements"):
        run_case(load_case(path))


def test_a_plate_without_its_extra_is_an_input_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Without pyfe3d a `plate:` panel stops at its file, line and key with the install
    command (exit 2), and two sources are refused."""
    import sys

    from typer.testing import CliRunner

    from cli.app import app

    monkeypatch.setitem(sys.modules, "pyfe3d", None)  # `import pyfe3d` fails
    monkeypatch.setenv("LOADS_CACHE_DIR", str(tmp_path / "cache"))  # no reduction cached
    path = tmp_path / "plate.case.yaml"
    path.write_text(PANEL.replace("grillage:", "plate:"), "utf-8")
    result = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "plate.case.yaml:6:" in result.output
    assert "pip install 'loads[plate]'" in result.output
    plate = "plate: {at: [0, 0, 0], size: [1, 1], thickness: 1, material: {E: 1, nu: 0, rho: 1}}"
    both = PANEL.replace("        grillage:", f"        {plate}\n        grillage:")
    path.write_text(both, "utf-8")
    with pytest.raises(InputError, match="exactly one source"):
        load_case(path)
