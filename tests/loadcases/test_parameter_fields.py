"""Parameters named in numeric fields, swept by a set (SPEC 1.4's `sweep: {clearance: ...}`):
the ball-in-socket case with its clearance a parameter settles at each swept clearance plus
the Hertz deflection under its weight (the same for every clearance: within 1e-7 m)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from cli.app import app
from loadcases.results.files import read_results

LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification"


def test_swept_clearance_reaches_the_geometry(tmp_path: Path) -> None:
    text = (LIBRARY / "ball_in_socket.case.yaml").read_text(encoding="utf-8")
    text = text.replace("radius: 10, clearance: 0.5}", "radius: 10, clearance: clearance}")
    text = text.replace(
        "  name: rod-end-ball\n", "  name: rod-end-ball\n  parameters: {clearance: 0.5 mm}\n"
    )
    text = text.replace("  end: 0.3 ", "  end: 0.15 ")
    (tmp_path / "socket.case.yaml").write_text(text, encoding="utf-8")
    (tmp_path / "clearances.set.yaml").write_text(
        "set: clearances\ncases: [socket.case.yaml]\n"
        "sweep: {clearance: ['0.1 mm', '0.3 mm', '0.5 mm']}\n",
        encoding="utf-8",
    )
    result = CliRunner().invoke(
        app,
        ["run", str(tmp_path / "clearances.set.yaml"), "-o", str(tmp_path / "out"), "--jobs", "1"],
    )
    assert result.exit_code == 0, result.output
    settled = {}
    for clearance, written in ((1e-4, "0.1mm"), (3e-4, "0.3mm"), (5e-4, "0.5mm")):
        # the run name keeps the value as the set wrote it
        csv = tmp_path / "out" / "clearances" / f"ball-in-socket-drop[clearance={written}].csv"
        _, channels = read_results(csv)
        settled[clearance] = channels["eccentricity.value"][-1]
    deflection = {c: e - c for c, e in settled.items()}
    assert all(d > 0 for d in deflection.values())
    assert np.ptp(list(deflection.values())) < 1e-7


def test_initial_value_named_by_a_parameter_is_not_read_in_the_file_unit(
    tmp_path: Path,
) -> None:
    """`initial: {hinge: {value: start}}` with `start: 30 deg` in a case whose bare angles
    are degrees: 30 deg (0.5236 rad), not 0.5236 deg (the SI value read again in the
    file's unit, as before 0.10.0)."""
    import math

    from loadcases.inputs.loader import load_case

    (tmp_path / "c.case.yaml").write_text(
        "case: start\nunits: {angle: deg}\nparameters: {start: 30 deg}\n"
        "mechanism:\n"
        "  bodies: {bar: {mass: 2, cm: [0.5, 0, 0], inertia: [1e-4, 0.2, 0.2]}}\n"
        "  joints: {hinge: {type: revolute, bodies: [bar, ground], at: [0, 0, 0],"
        " axis: [0, 0, 1]}}\n"
        "initial: {hinge: {value: start}}\nanalysis: {type: static}\n",
        encoding="utf-8",
    )
    case = load_case(tmp_path / "c.case.yaml").case
    assert case.initial["hinge"].value == math.radians(30.0)
