"""The asymmetric hinge lines of the solar-array library (bepicolombo_asym.mech.yaml; seed
003 3.3.1, 4.1.3): HL2 as its two hinges (A an inline joint at z = +500 mm, B a spherical
joint at z = -500 mm), the SADM 100 mm off the wing's middle. Hand statics and momentum:

- weight along the hinge lines, hinge lines locked (static): hinge A carries the couple
  of the outboard panel's weight about B, F_A = (0.9 W_o, -0.015 W_o, 0) from the lever
  arms (0.9 m across HL2, 15 mm out of its plane, 1 m between the hinges), B the rest;
  the SADM the whole weight and its moment (0.05 W_i + 0.08 W_o, -0.9 (W_i + W_o)) N*m
  about the SADM point. 1e-9 relative (measured ~1e-15).
- latch-up in orbit: the SADM is the only external load, the motion is planar and the
  wing's centre of mass lies e = 0.1 m above the SADM point along the hinge lines, so
  dH/dt about the SADM point gives Tx = -e Fy and Ty = e Fx (out-of-plane torques the
  symmetric file cannot have), 1e-6 of the peak (measured ~1e-13).
- the choice of joints: the spherical and inline pair runs (no redundant equation: a
  redundant one refuses the run); a revolute at hinge B instead repeats hinge A's two
  rotations and the run is refused, naming them at joints.hl2_b.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import LIBRARY, solve_case

WING = LIBRARY.parent / "solar_array"
G = 9.81
M_IN, M_OUT = 8.4658, 4.63  # kg (bepicolombo.mech.yaml)
E_SADM = 0.1  # m, wing cm above the SADM point along z (bepicolombo_asym.mech.yaml)

STATIC = """case: asym-weight
mechanism: {mechanism}
effects: {{friction: false, damping: false}}
phases:
  - {{name: weight, analysis: {{type: static}}, locks: [hl2, sadm]}}
requests:
  sadm: {{joint: sadm, quantity: force, frame: ground}}
  hinge_a: {{joint: hl2, quantity: force, frame: ground}}
  hinge_b: {{joint: hl2_b, quantity: force, frame: ground}}
"""


def _column(solution, name: str) -> np.ndarray:
    return np.asarray(solution.channels[name])


def test_weight_shared_by_the_hinges_as_hand_statics(tmp_path: Path) -> None:
    case = tmp_path / "weight.case.yaml"
    case.write_text(STATIC.format(mechanism=WING / "bepicolombo_asym.mech.yaml"))
    s = solve_case(case)
    w_in, w_out = M_IN * G, M_OUT * G
    expected = {
        "hinge_a.fx": 0.9 * w_out,
        "hinge_a.fy": -0.015 * w_out,
        "hinge_a.fz": 0.0,
        "hinge_b.fx": -0.9 * w_out,
        "hinge_b.fy": 0.015 * w_out,
        "hinge_b.fz": w_out,
        "sadm.fx": 0.0,
        "sadm.fy": 0.0,
        "sadm.fz": w_in + w_out,
        "sadm.tx": 0.05 * w_in + 0.08 * w_out,
        "sadm.ty": -0.9 * (w_in + w_out),
    }
    for name, value in expected.items():
        assert _column(s, name)[-1] == pytest.approx(value, abs=1e-9 * (w_in + w_out)), name


def test_latch_up_sadm_torques_from_the_offset() -> None:
    s = solve_case(WING / "bepicolombo_asym_latchup.case.yaml")
    fx, fy = _column(s, "sadm_force.fx"), _column(s, "sadm_force.fy")
    tx, ty = _column(s, "sadm_force.tx"), _column(s, "sadm_force.ty")
    peak = float(np.max(np.hypot(tx, ty)))
    assert peak > 5.0  # N*m: the out-of-plane torques are there (8.6 N*m measured)
    np.testing.assert_allclose(tx, -E_SADM * fy, rtol=0, atol=1e-6 * peak)
    np.testing.assert_allclose(ty, E_SADM * fx, rtol=0, atol=1e-6 * peak)
    # the hinges of HL2 share the latch-up load, each half (the panels' cm midway)
    a, b = _column(s, "hinge_a.f"), _column(s, "hinge_b.f")
    assert float(np.max(a)) > 10.0
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-6 * float(np.max(a)))


def test_a_revolute_at_each_hinge_is_refused_as_redundant(tmp_path: Path) -> None:
    from loadcases.foundation.diagnostics import InputError
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    for name in ("bepicolombo.mech.yaml", "bepicolombo_asym.mech.yaml"):
        (tmp_path / name).write_text((WING / name).read_text())
    variant = tmp_path / "bepicolombo_asym.mech.yaml"
    spherical = (
        "hl2_b: {type: spherical, bodies: [wing_outboard, wing_inboard], at: [1800, 65, -500]}"
    )
    text = variant.read_text()
    assert spherical in text
    variant.write_text(
        text.replace(
            spherical,
            "hl2_b: {type: revolute, bodies: [wing_outboard, wing_inboard], "
            "at: [1800, 65, -500], axis: [0, 0, -1]}",
        )
    )
    case = tmp_path / "weight.case.yaml"
    case.write_text(STATIC.format(mechanism=variant.name))
    with pytest.raises(InputError) as refused:
        run_case(load_case(case))
    messages = [d.message for d in refused.value.diagnostics]
    assert messages and all("redundant constraint: hl2_b" in m for m in messages), messages
    assert all(d.key == "joints.hl2_b" for d in refused.value.diagnostics)
