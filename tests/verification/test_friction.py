"""The element verification cases of loadcases/library/verification/elements, run by `loads`:
pin friction in quasi-static (hand statics) and the closed cable loop (seed 003 eqs. 2.3-2.6).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import LIBRARY

G, MASS, LENGTH = 9.81, 2.0, 1.0


def _run(name: str, tmp_path: Path):
    """Run library/verification/elements/NAME as `loads run` does; the solver must succeed."""
    from loadcases.run import run_file

    (outcome,) = run_file(LIBRARY / "elements" / name, output_dir=tmp_path)
    assert outcome.solution.status == "ok", outcome.solution.message
    return outcome.solution


def test_pin_friction_case(tmp_path: Path) -> None:
    """drive = m g L/2 cos(angle) + mu r m g + preload after the first row (no travel yet
    there: no friction). Tolerance 1e-9 N*m (static Newton to 1e-10 of the weight)."""
    sol = _run("pin_friction.case.yaml", tmp_path)
    angle, drive = sol.channels["angle.value"], sol.channels["drive.value"]
    expected = MASS * G * LENGTH / 2 * np.cos(angle) + 0.2 * 0.01 * MASS * G + 0.5
    expected[0] -= 0.2 * 0.01 * MASS * G + 0.5
    np.testing.assert_allclose(drive, expected, atol=1e-9)


def test_cable_loop_case(tmp_path: Path) -> None:
    """Eqs. 2.3-2.6 by hand with phi1 = -10 deg, phi2 = 5 deg; the holding torques are
    T1 (hl1 turns the yoke against pulley 1) and -T2. Tolerance 1e-9 relative."""
    r1, r2, k, t0 = 0.05, 0.04, 1e4, 200.0
    e = r1 * math.radians(-10.0) - r2 * math.radians(5.0)
    fa, fb = t0 + k * e, t0 - k * e
    d = 1.0
    c = {key: v[0] for key, v in _run("cable_loop.case.yaml", tmp_path).channels.items()}
    assert c["ccl.t1"] == pytest.approx(r1 * (fb - fa), rel=1e-9)
    assert c["ccl.t2"] == pytest.approx(r2 * (fa - fb), rel=1e-9)
    assert c["ccl.f_axial"] == pytest.approx(
        (fa + fb) * math.sqrt(d * d - (r1 - r2) ** 2) / d, rel=1e-9
    )
    assert c["ccl.f_lateral"] == pytest.approx((fa - fb) * (r1 - r2) / d, rel=1e-9)
    assert c["hold1.value"] == pytest.approx(r1 * (fb - fa), rel=1e-9)
    assert c["hold2.value"] == pytest.approx(-r2 * (fa - fb), rel=1e-9)


def test_guided_cable_loop_from_yaml(tmp_path: Path) -> None:
    """The same case with `guided: true` (seed 003 fig. 2.2.5-4): the yoke takes
    (F_a - F_b)(r1 - r2) = -2.443 N*m, no lateral force, F_ax = F_a + F_b; the holding
    torques are unchanged (the wing's moment balance about hl1 holds either way).
    Tolerance 1e-9 relative."""
    from loadcases.run import run_file

    r1, r2, k, t0 = 0.05, 0.04, 1e4, 200.0
    e = r1 * math.radians(-10.0) - r2 * math.radians(5.0)
    fa, fb = t0 + k * e, t0 - k * e
    text = (LIBRARY / "elements" / "cable_loop.case.yaml").read_text("utf-8")
    text = text.replace("pretension: 200}", "pretension: 200, guided: true}")
    assert "guided: true" in text
    path = tmp_path / "guided.case.yaml"
    path.write_text(text, "utf-8")
    (outcome,) = run_file(path, output_dir=tmp_path)
    c = {key: v[0] for key, v in outcome.solution.channels.items()}
    assert c["ccl.t_yoke"] == pytest.approx((fa - fb) * (r1 - r2), rel=1e-9)
    assert c["ccl.f_lateral"] == 0.0
    assert c["ccl.f_axial"] == pytest.approx(fa + fb, rel=1e-9)
    assert c["hold1.value"] == pytest.approx(r1 * (fb - fa), rel=1e-9)
    assert c["hold2.value"] == pytest.approx(-r2 * (fa - fb), rel=1e-9)
