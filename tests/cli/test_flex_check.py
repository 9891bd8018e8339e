"""`loads flex check`: the printed free-free frequencies of steel beams (1 m, 20 x 20 mm)
against closed forms.

- One element (2 nodes): the discrete model's own closed forms (derived from the consistent
  12-DOF element by its symmetric and antisymmetric shapes): axial sqrt(12 E / rho) / L,
  torsion sqrt(12 GJ / (rho Ip)) / L, bending sqrt(720 EI / (rho A L^4)) and
  sqrt(8400 EI / (rho A L^4)) in each plane; equal to the 9 printed digits.
- Nine elements (10 nodes): the continuous free-free Euler-Bernoulli beam, beta L =
  4.730040745 and 7.853204624 (Blevins, Formulas for natural frequency and mode shape,
  table 8-1); the discretisation error measured 5.09e-5 and 3.72e-4 for the first two
  bending pairs (106.3374 Hz against 106.3320 Hz for the first).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from typer.testing import CliRunner

from cli.app import app
from loadcases.flexible.neutral import write_neutral
from mechlib.flexible.fe_model import FEModel
from tests.loadcases.flexible.beam import Beam, assembled

runner = CliRunner()
E, G, RHO, SIDE, LENGTH = 210e9, 80.77e9, 7850.0, 0.02, 1.0
A, AREA_MOMENT, J, IP = SIDE**2, SIDE**4 / 12, 0.1406 * SIDE**4, SIDE**4 / 6


def _steel(elements: int) -> Beam:
    h = LENGTH / elements
    return Beam(E * A, E * AREA_MOMENT, E * AREA_MOMENT, G * J, RHO * A, RHO * IP, h)


def _write(folder: Path, elements: int) -> Path:
    K, M, x = assembled(_steel(elements), elements)
    n = elements + 1
    model = FEModel(
        np.arange(1, n + 1) * 10,
        np.column_stack([x, np.zeros(n), np.zeros(n)]),
        np.column_stack([np.repeat(np.arange(n), 6), np.tile(np.arange(6), n)]),
        sp.csr_matrix(K),
        sp.csr_matrix(M),
        (0, n - 1),
    )
    header, _ = write_neutral(
        folder / "beam", model, description="steel beam", node_names={"root": 0}
    )
    return header


def _printed(output: str) -> tuple[np.ndarray, int]:
    """The printed frequencies (Hz) and how many are flagged rigid-body."""
    rows = re.findall(r"^\s+\d+\s+(\S+)(  rigid-body)?$", output, flags=re.M)
    return np.array([float(value) for value, _ in rows]), sum(1 for _, r in rows if r)


def test_two_node_beam(tmp_path: Path) -> None:
    result = runner.invoke(app, ["flex", "check", str(_write(tmp_path, 1)), "--modes", "12"])
    assert result.exit_code == 0, result.output
    hertz, rigid = _printed(result.output)
    assert rigid == 6 and np.all(np.abs(hertz[:6]) < 1e-3)
    bending = [np.sqrt(c * E * AREA_MOMENT / (RHO * A * LENGTH**4)) for c in (720, 720, 8400, 8400)]
    axial = np.sqrt(12 * E / RHO) / LENGTH
    torsion = np.sqrt(12 * G * J / (RHO * IP)) / LENGTH
    expected = np.sort([*bending, axial, torsion]) / (2 * np.pi)
    assert np.max(np.abs(hertz[6:] / expected - 1)) < 1e-8
    assert "mass: [3.14, 3.14, 3.14] kg (x, y, z); centre of mass: [0.5, 0, 0] m" in result.output
    assert "10 (root) at [0, 0, 0] m" in result.output and "20 at [1, 0, 0] m" in result.output
    assert "nodes: 2 (2 with six DOF); DOF: 12" in result.output


def test_ten_node_beam(tmp_path: Path) -> None:
    result = runner.invoke(app, ["flex", "check", str(_write(tmp_path, 9)), "--modes", "10"])
    assert result.exit_code == 0, result.output
    hertz, rigid = _printed(result.output)
    assert rigid == 6 and len(hertz) == 10
    base = np.sqrt(E * AREA_MOMENT / (RHO * A)) / (2 * np.pi * LENGTH**2)
    first, second = (beta**2 * base for beta in (4.730040744862704, 7.853204624095838))
    assert np.max(np.abs(hertz[6:8] / first - 1)) < 6e-5  # measured 5.09e-5
    assert np.max(np.abs(hertz[8:10] / second - 1)) < 4.5e-4  # measured 3.72e-4


def test_bad_file_exits_2(tmp_path: Path) -> None:
    header = tmp_path / "bad.json"
    header.write_text('{"format": "npz", "units": {"length": "mm"}}')
    result = runner.invoke(app, ["flex", "check", str(header)])
    assert result.exit_code == 2
    assert "missing unit: force or mass" in result.output


@pytest.mark.parametrize("args", [["nowhere.json"], ["--modes", "0"]])
def test_usage_errors(tmp_path: Path, args: list[str]) -> None:
    header = _write(tmp_path, 1)
    arguments = ["flex", "check", *(args if args[0] != "--modes" else [str(header), *args])]
    result = runner.invoke(app, arguments)
    assert result.exit_code == 2
    assert "loads: error:" in result.output


def _table(output: str, title: str) -> np.ndarray:
    """The rows of the printed comparison `title` (mode, full, then value and diff per
    reduction; NaN where a reduction has no such mode)."""
    block = output.split(title, 1)[1].split("model against", 1)[1].splitlines()[2:]
    rows = []
    for line in block:
        if not re.match(r"^\s+\d+\s+\S+\s+\S", line):
            break
        cells: list[float] = []
        for c in line.split():  # a missing mode is one "-" for its value and difference
            cells += [np.nan, np.nan] if c == "-" else [float(c.rstrip("%"))]
        rows.append(cells)
    return np.array(rows)


def test_reduced_frequencies_beside_the_full_model(tmp_path: Path) -> None:
    """The seed's Tables 3-2/3-3 in form for the nine-element beam held at both ends:
    free-free, the reductions are Rayleigh-Ritz upper bounds of the full model's modes,
    within 1e-4 for the first bending pair with 10 fixed-interface modes (measured 7.2e-5)
    and 0.36 % with 2; held, the reduced model has exactly its kept modes (1e-9), and the
    full model's are the clamped-clamped Euler-Bernoulli beam's, beta L = 4.730040745 as
    free-free (Blevins table 8-1; measured 5.3e-5, the mesh)."""
    result = runner.invoke(
        app, ["flex", "check", str(_write(tmp_path, 9)), "--modes", "6", "--reduced", "2,10"]
    )
    assert result.exit_code == 0, result.output
    free = _table(result.output, "free-free elastic modes")
    held = _table(result.output, "fixed-interface modes")
    assert free[:, 0].tolist() == [7, 8, 9, 10, 11, 12]
    full, two, ten = free[:, 1], free[:, 2], free[:, 4]
    assert np.all(two >= full * (1 - 1e-9)) and np.all(ten >= full * (1 - 1e-9))
    assert np.all(ten <= two * (1 + 1e-9))
    assert np.max(np.abs(ten[:2] / full[:2] - 1)) < 1e-4
    assert two[0] / full[0] - 1 == pytest.approx(3.56e-3, abs=1e-4)
    assert free[0, 3] == pytest.approx(100 * (two[0] / full[0] - 1), abs=1e-4)  # printed %
    assert np.max(np.abs(held[:2, 2] / held[:2, 1] - 1)) < 1e-8
    assert np.all(np.isnan(held[2:, 2]))  # two kept: no third held mode
    assert np.max(np.abs(held[:, 4] / held[:, 1] - 1)) < 1e-8
    base = np.sqrt(E * AREA_MOMENT / (RHO * A)) / (2 * np.pi * LENGTH**2)
    assert np.max(np.abs(held[:2, 1] / (4.730040744862704**2 * base) - 1)) < 1e-4


MECHANISM = """\
units: {length: mm}
bodies:
  arm: {mass: 1, cm: [0, 0, 0], inertia: [1, 1, 1]}
  beam:
    flexible:
      beam:
        start: [0, 0, 0]
        end: [1000, 0, 0]
        section: {width: 20, height: 20, shear: false}
        material: {E: 210 GPa, nu: 0.3, rho: 7850 kg/m^3}
        elements: 20
      interface: {root: [0, 0, 0], tip: [1000, 0, 0]}
joints:
  pin: {type: revolute, bodies: [beam, arm], at: [0, 0, 0], axis: [0, 0, 1]}
"""


def test_flexible_body_of_a_mechanism_file(tmp_path: Path) -> None:
    """`--body`: a mechanism's beam before reduction (20 elements, both ends interface):
    free-free and held (clamped-clamped) first bending pairs at the Euler-Bernoulli beta L =
    4.730040745 (Blevins table 8-1) within 1e-3 (measured -8.2e-4 for both: the engine's
    beam mass carries the section's rotary inertia, which the Euler-Bernoulli value leaves
    out); a rigid body or none is a usage error naming the flexible bodies."""
    path = tmp_path / "beam.mech.yaml"
    path.write_text(MECHANISM, "utf-8")
    result = runner.invoke(app, ["flex", "check", str(path), "--body", "beam", "--reduced", "4"])
    assert result.exit_code == 0, result.output
    assert "flexible body beam, its full FE model" in result.output
    assert "21 (21 with six DOF)" in result.output and "(tip) at [1, 0, 0] m" in result.output
    free = _table(result.output, "free-free elastic modes")
    held = _table(result.output, "fixed-interface modes")
    base = np.sqrt(E * AREA_MOMENT / (RHO * A)) / (2 * np.pi * LENGTH**2)
    first = 4.730040744862704**2 * base
    assert np.max(np.abs(free[:2, 1] / first - 1)) < 1e-3
    assert np.max(np.abs(held[:2, 1] / first - 1)) < 1e-3
    for args in (["--body", "arm"], []):
        wrong = runner.invoke(app, ["flex", "check", str(path), *args])
        assert wrong.exit_code == 2 and "its flexible bodies: beam" in wrong.output
