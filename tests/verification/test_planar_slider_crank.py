"""The slider-crank of SPEC 1.2 (loadcases/library/verification/slider_crank.mech.yaml,
revolute, spherical, universal, prismatic) with `plane: xy` added and nothing else changed,
against the 3-D file: kinematic (one crank revolution) and quasi-static runs.

In the plane the spherical and the universal (axes z, y) joints act as revolutes; every
in-plane column (slider and crank positions, in-plane reaction forces, the drive torque)
must equal the 3-D one within 1e-9 of its peak (both exact to the Newton tolerance;
measured 1e-14), and `loads run` of a planar file that leaves the plane exits 2 naming the
key.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from cli.app import app
from loadcases.run import check_mechanism_file, run_file

LIBRARY = Path(__file__).parents[2] / "loadcases" / "library" / "verification"
_IN_PLANE = ("fx", "fy", "x", "y", "value")
_FLOOR = 1e-12  # SI: round-off of a column that is 0


def _case(folder: Path, analysis: str, planar: bool) -> Path:
    """The library's slider-crank case (coarser output) on a copy of its mechanism, with
    `plane: xy` when `planar`."""
    mech = (LIBRARY / "slider_crank.mech.yaml").read_text()
    if planar:
        mech = mech.replace("name: slider-crank\n", "name: slider-crank\nplane: xy\n")
        assert "plane: xy" in mech
    tag = f"{'planar' if planar else 'space'}_{analysis}"
    (folder / f"{tag}.mech.yaml").write_text(mech)
    case = (LIBRARY / "slider_crank.case.yaml").read_text()
    case = case.replace("mechanism: slider_crank.mech.yaml", f"mechanism: {tag}.mech.yaml")
    case = case.replace("type: kinematic", f"type: {analysis}").replace("step: 0.001", "step: 0.02")
    path = folder / f"{tag}.case.yaml"
    path.write_text(case)
    return path


@pytest.mark.parametrize("analysis", ["kinematic", "quasi-static"])
def test_planar_file_matches_the_3d_file(tmp_path: Path, analysis: str) -> None:
    """Same columns, in-plane ones within 1e-9 of their peak; the planar run notes that
    its out-of-plane reactions are reported as 0."""
    planar, space = (
        run_file(_case(tmp_path, analysis, p), output_dir=tmp_path / str(p))[0].solution
        for p in (True, False)
    )
    assert planar.status == space.status == "ok"
    assert set(planar.channels) == set(space.channels)
    for name, column in space.channels.items():
        if name.rsplit(".", 1)[1] in _IN_PLANE:
            gap = np.abs(planar.channels[name] - column).max()
            assert gap <= 1e-9 * np.abs(column).max() + _FLOOR, name
    assert any("reported as 0" in w for w in planar.warnings)


def test_mechanism_check_counts_planar_equations(tmp_path: Path) -> None:
    """`loads run X.mech.yaml`: 17 equations in 3-D (5 + 3 + 4 + 5), 8 in the plane (2 per
    joint: the universal's cross-axis equation is met by any planar motion); 1 DOF both."""
    _case(tmp_path, "kinematic", True), _case(tmp_path, "kinematic", False)
    assert check_mechanism_file(tmp_path / "planar_kinematic.mech.yaml") == [
        "planar_kinematic.mech.yaml: planar mechanism (xy) with 3 bodies, 8 constraint "
        "equations, 1 degree of freedom"
    ]
    assert check_mechanism_file(tmp_path / "space_kinematic.mech.yaml") == [
        "space_kinematic.mech.yaml: mechanism with 3 bodies, 17 constraint equations, "
        "1 degree of freedom"
    ]


def test_leaving_the_plane_exits_2_naming_the_key(tmp_path: Path) -> None:
    """A guide along z in a planar (xy) slider-crank: exit 2, file:line:column and key."""
    case = _case(tmp_path, "kinematic", True)
    mech = tmp_path / "planar_kinematic.mech.yaml"
    text = mech.read_text().replace("axis: [1, 0, 0]", "axis: [0, 0, 1]")
    mech.write_text(text)
    line = next(i for i, row in enumerate(text.splitlines(), 1) if row.startswith("  guide:"))
    column = text.splitlines()[line - 1].index("axis:") + 1
    result = CliRunner().invoke(app, ["run", str(case), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2
    assert (
        f"planar_kinematic.mech.yaml:{line}:{column}: error: joints.guide.axis: the axis of a "
        "prismatic joint must lie in plane xy"
    ) in result.output


def test_modes_of_a_planar_file_exit_2_at_the_analysis(tmp_path: Path) -> None:
    """A modes analysis needs the 3-D model: `loads validate` exits 2 at `analysis`."""
    case = _case(tmp_path, "modes", True)
    text = case.read_text()
    case.write_text(text[: text.index("analysis:")] + "analysis: {type: modes}\n")
    result = CliRunner().invoke(app, ["validate", str(case)])
    assert result.exit_code == 2
    assert "error: analysis: a modes analysis needs the 3-D model: remove `plane`" in result.output
