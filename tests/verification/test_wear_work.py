"""Wear work of a clearance joint against a closed form, and the wear map's bookkeeping.

Case (written here): a ball fixed to ground with its centre 0.51 mm from the centre of a
socket of 0.5 mm clearance (geometry `offset`, so it presses 0.01 mm into the wall at
polar angle 0), the socket turning about z by phi(t) = 2 t + 3 t^2 rad (kinematic
analysis). Closed form: the penetration stays delta = 1e-5 m and its rate 0, so
F_N = K delta^1.5 (Hertz, the Lankarani-Nikravesh factor is 1 at zero rate); the contact
point lies rho = R + c + delta/2 from the turning axis (midway between the surfaces), so
v_rel = rho phi' and the wear work is W(t) = K delta^1.5 rho phi(t). Tolerance 1e-6
relative (the engine integrates F_N v_rel by the trapezoidal rule over each step; v_rel is
linear in t here, so the rule is exact up to rounding: measured 2e-15).
Archard depth (the `wear:` law): depth(t) = k W(t) / (H * 2 pi (R + c) b), the same
closed form through the wear work (k = 1e-4, H = 2 GPa, b = 2 mm), 1e-6 relative.
The wear map adds each output interval's wear-work increment to one sector: its sectors
add up to the run's wear work to rounding (1e-12), and at polar angle 0 all of it lies in
sector 0.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

K, DELTA, R, C = 1.0e10, 1.0e-5, 0.01, 5.0e-4
WEAR_K, HARDNESS, TRACK = 1.0e-4, 2.0e9, 2.0e-3
RHO = R + C + DELTA / 2

CASE = f"""
case: wear-closed-form
mechanism:
  name: turning-socket
  gravity: [0, 0, 0]
  bodies:
    ball:   {{mass: 0.2, cm: [{C + DELTA}, 0, 0], inertia: [8.0e-6, 8.0e-6, 8.0e-6]}}
    socket: {{mass: 0.3, cm: [0, 0, 0], inertia: [3.0e-5, 3.0e-5, 3.0e-5]}}
  joints:
    hold: {{type: fixed, bodies: [ball, ground], at: [{C + DELTA}, 0, 0]}}
    spin: {{type: revolute, bodies: [socket, ground], at: [0, 0, 0], axis: [0, 0, 1]}}
  contacts:
    rod_end:
      type: hertz
      bodies: [ball, socket]
      geometry: {{shape: sphere_in_sphere, center: [0, 0, 0], radius: {R}, clearance: {C},
                 offset: [{C + DELTA}, 0, 0]}}
      stiffness: {K}
      restitution: 0.5
      friction: {{mu_static: 0.15, mu_dynamic: 0.1}}
      wear: {{coefficient: {WEAR_K}, hardness: {HARDNESS}, track_width: {TRACK}}}
motions:
  turn: {{joint: spin, value: "2 * t + 3 * t * t"}}
analysis: {{type: kinematic, end: 1.0, step: 0.01}}
requests:
  polar: {{contact: rod_end, quantity: polar}}
  work:  {{contact: rod_end, quantity: wear_work}}
  depth: {{contact: rod_end, quantity: wear_depth}}
  angle: {{joint: spin, quantity: angle}}
"""


@pytest.fixture(scope="module")
def solution(tmp_path_factory: pytest.TempPathFactory):
    from conftest import estimate_off

    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    path = tmp_path_factory.mktemp("wear") / "wear.case.yaml"
    path.write_text(CASE)
    outcome = run_case(estimate_off(load_case(path)))
    assert outcome.solution.ok, outcome.solution.message
    return outcome.solution


def test_wear_work_closed_form(solution) -> None:
    t = np.asarray(solution.time)
    phi = 2 * t + 3 * t * t
    assert np.asarray(solution.channels["angle.value"]) == pytest.approx(phi, abs=1e-12)
    normal = K * DELTA**1.5
    assert np.asarray(solution.channels["polar.normal"]) == pytest.approx(normal, rel=1e-9)
    wear = np.asarray(solution.channels["polar.wear"])
    assert wear == pytest.approx(normal * RHO * (2 + 6 * t), rel=1e-9)
    work = np.asarray(solution.channels["work.value"])
    assert work == pytest.approx(normal * RHO * phi, rel=1e-6, abs=1e-9)
    assert np.array_equal(work, np.asarray(solution.channels["polar.wear_work"]))


def test_archard_depth_closed_form(solution) -> None:
    """depth = k F_N rho phi / (H 2 pi (R + c) b) for the constant force sliding rho phi."""
    t = np.asarray(solution.time)
    work = K * DELTA**1.5 * RHO * (2 * t + 3 * t * t)
    expected = WEAR_K * work / (HARDNESS * 2 * math.pi * (R + C) * TRACK)
    depth = np.asarray(solution.channels["depth.value"])
    assert depth == pytest.approx(expected, rel=1e-6, abs=1e-15)


def test_polar_columns_of_the_offset_ball(solution) -> None:
    """The ball presses on the socket at polar angle -phi (socket axes: the socket turns
    under the fixed ball), 0.51 mm from its centre, in the plane normal to z."""
    phi = 2 * np.asarray(solution.time) + 3 * np.asarray(solution.time) ** 2
    assert np.asarray(solution.channels["polar.radial"]) == pytest.approx(C + DELTA, rel=1e-12)
    assert np.abs(solution.channels["polar.axial"]).max() < 1e-15
    expected = np.arctan2(np.sin(-phi), np.cos(-phi))
    assert np.asarray(solution.channels["polar.angle"]) == pytest.approx(expected, abs=1e-12)
    assert np.all(np.asarray(solution.channels["polar.clearance"]) == C)


def test_wear_map_sectors(solution) -> None:
    """Sectors add up to the wear work (1e-12); each sector the socket turned through
    entirely holds F_N rho x its width, within one output interval's increment at either
    end (the interval goes whole to the sector of its mean angle)."""
    from loadcases.report.wear_map import SECTORS, wear_sectors

    work = np.asarray(solution.channels["polar.wear_work"])
    sectors = wear_sectors(np.asarray(solution.channels["polar.angle"]), work)
    assert sectors.shape == (SECTORS,)
    assert sectors.sum() == pytest.approx(work[-1], rel=1e-12)
    width = 2 * math.pi / SECTORS
    full = K * DELTA**1.5 * RHO * width
    phi_end = 5.0  # rad turned: sectors centred at -k * 10 deg, k = 1 .. 27, are inside
    inside = [SECTORS - k for k in range(1, int((phi_end - width / 2) / width))]
    assert np.abs(sectors[inside] - full).max() <= 2 * np.diff(work).max()


def test_wear_sectors_wrap_and_split() -> None:
    """Intervals straddling +-pi go to the sector at 180 deg; each sector gets its own."""
    from loadcases.report.wear_map import wear_sectors

    angle = np.array([math.pi - 0.01, -math.pi + 0.01, math.pi / 2, math.pi / 2])
    work = np.array([0.0, 1.0, 1.5, 4.0])
    sectors = wear_sectors(angle, work, 4)  # sectors centred on 0, 90, 180, 270 deg
    # intervals: (pi-0.01 -> -pi+0.01): mean pi -> sector 2 (+1); (-pi+0.01 -> pi/2): mean
    # angle about 3 pi/4 + ... -> sector 1 or 2; (pi/2 -> pi/2): sector 1 (+2.5)
    assert sectors.sum() == pytest.approx(4.0, rel=1e-15)
    assert sectors[2] >= 1.0 and sectors[1] >= 2.5
    assert sectors[0] == sectors[3] == 0.0


def test_polar_plots_and_sheet(solution, tmp_path: Path) -> None:
    """`loads plot --polar` draws the polar plot and the wear map; the workbook's sheet
    holds the run's wear work and its sectors (read back)."""
    import openpyxl
    from matplotlib.image import imread
    from typer.testing import CliRunner

    from cli.app import app
    from loadcases.report.wear_map import wear_map_sheet
    from loadcases.results.saved import SavedRun

    run = SavedRun(
        "wear-closed-form",
        np.asarray(solution.time),
        {k: np.asarray(v) for k, v in solution.channels.items()},
        {"polar.angle": "rad"},
    )
    book = openpyxl.Workbook()
    book.add_named_style(_header_style())
    assert wear_map_sheet(book.active, [run]) == 1
    rows = list(book.active.iter_rows(values_only=True))
    assert rows[1][:2] == ("wear-closed-form", "polar")
    work = float(solution.channels["polar.wear_work"][-1])
    assert rows[1][2] == pytest.approx(work, rel=1e-15)
    assert sum(rows[1][6:]) == pytest.approx(work, rel=1e-12)  # the sectors
    assert rows[0][6] == "0 deg [J]" and rows[0][-1] == "350 deg [J]"

    results = tmp_path / "results"
    case = tmp_path / "wear.case.yaml"
    case.write_text(CASE)
    runner = CliRunner()
    result = runner.invoke(app, ["run", str(case), "-o", str(results)])
    assert result.exit_code == 0, result.output
    out = tmp_path / "plots"
    result = runner.invoke(app, ["plot", str(results), "--polar", "polar", "-o", str(out)])
    assert result.exit_code == 0, result.output
    for name in ("wear-closed-form-polar-polar.png", "wear-closed-form-polar-wear-map.png"):
        assert imread(out / name).shape[0] > 400
    result = runner.invoke(app, ["plot", str(results), "--polar", "nothing", "-o", str(out)])
    assert result.exit_code == 2
    assert "no polar request 'nothing'" in result.output


def _header_style():
    from openpyxl.styles import NamedStyle

    return NamedStyle(name="loads header")
