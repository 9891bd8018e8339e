"""Four-bar cases: quasi-static torque by virtual work, and redundancy handling.

Cases (loadcases/library/verification): fourbar_quasistatic.case.yaml (revolute, spherical,
universal, revolute: no redundant constraint), fourbar_redundant.case.yaml (four revolutes:
must be refused, naming the redundant equations) and fourbar_redundant_drop.case.yaml (the
same with `redundant: drop`: runs and warns). References: references.fourbar_drive_torque
(virtual work with loop-closure velocity ratios) and references.fourbar_static_loads
(planar statics of each link).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from references import (
    FourBar,
    all_warnings,
    assert_within_peak,
    channel,
    fourbar_drive_torque,
    fourbar_pose,
    fourbar_static_loads,
    vector,
    wrap_angle,
)

CRANK_SPEED = 2 * np.pi  # rad/s, `crank_speed: 360 deg/s`
FOURBAR = FourBar()  # geometry and masses of the case files (SI)
LOOP_JOINTS = ("crank_pivot", "pin_b", "pin_c", "rocker_pivot")
PEAK_FRACTION = 1e-3
"""Quasi-static results within 0.1% of the channel's peak: each row is an exact equilibrium
(no integration error), so only the Newton tolerance remains; 0.1% is sizing accuracy."""


@pytest.fixture(scope="module")
def outcome(run_case):
    return run_case("fourbar_quasistatic.case.yaml")


def _crank_rotation(outcome) -> np.ndarray:
    """Crank rotation from design (rad) as imposed by the motion."""
    return CRANK_SPEED * np.asarray(outcome.solution.time, float)


def test_crank_and_rocker_angles(outcome) -> None:
    """crank_angle = crank_speed * t; rocker_angle = phi4 of the closed-form loop closure
    (both modulo 2 pi; 1e-7 rad, the constraint solver's tolerance)."""
    th = _crank_rotation(outcome)
    assert len(th) == 201
    crank = wrap_angle(channel(outcome, "crank_angle.value") - th)
    rocker = wrap_angle(channel(outcome, "rocker_angle.value") - fourbar_pose(th).phi4)
    assert np.max(np.abs(crank)) < 1e-7
    assert np.max(np.abs(rocker)) < 1e-7


def test_payload_position(outcome) -> None:
    """The coupler point `payload` (its centre of mass) moves as the loop closure says
    (1e-7 m, constraint tolerance; the coupler is 0.3 m long)."""
    th = _crank_rotation(outcome)
    pos = vector(outcome, "payload_pos")
    expected = fourbar_pose(th, FOURBAR).coupler_cm
    assert np.max(np.abs(pos[:, :2] - expected)) < 1e-7
    assert np.max(np.abs(pos[:, 2])) < 1e-7


def test_drive_torque_by_virtual_work(outcome) -> None:
    """drive_torque.value = g sum(m_i dy_Gi/dtheta) (virtual work, [RS 11.9]) within 0.1%
    of its peak (about 5.3 N*m)."""
    expected = fourbar_drive_torque(_crank_rotation(outcome), FOURBAR)
    assert_within_peak(
        channel(outcome, "drive_torque.value"), expected, PEAK_FRACTION, "drive_torque.value"
    )


@pytest.mark.parametrize("joint", LOOP_JOINTS)
def test_joint_reactions(outcome, joint: str) -> None:
    """In-plane reactions of every joint vs planar statics, within 0.1% of the peak in-plane
    force of that joint; out-of-plane components (fz, tx, ty) vanish to the same bound
    (moments scaled by the 0.1 m crank length)."""
    loads = fourbar_static_loads(_crank_rotation(outcome), FOURBAR)
    ref_x, ref_y = loads[f"{joint}_fx"], loads[f"{joint}_fy"]
    peak = float(np.max(np.hypot(ref_x, ref_y)))
    request = f"{joint}_force"
    assert_within_peak(
        channel(outcome, f"{request}.fx"), ref_x, PEAK_FRACTION, f"{request}.fx", peak
    )
    assert_within_peak(
        channel(outcome, f"{request}.fy"), ref_y, PEAK_FRACTION, f"{request}.fy", peak
    )
    assert np.max(np.abs(channel(outcome, f"{request}.fz"))) <= PEAK_FRACTION * peak
    for moment in ("tx", "ty"):
        values = channel(outcome, f"{request}.{moment}")
        assert np.max(np.abs(values)) <= PEAK_FRACTION * peak * 0.1, f"{request}.{moment}"


def test_redundant_fourbar_is_refused(tmp_path) -> None:
    """Four revolutes in a planar loop: 20 equations, 18 coordinates, 1 degree of freedom,
    so 3 equations are redundant (translation along z, rotations about x and y). The run is
    refused with an input error that names them by joint and direction (SPEC 1.2)."""
    from loadcases.foundation.diagnostics import InputError
    from loadcases.run import run_file

    with pytest.raises(InputError) as caught:
        run_file(CASES / "fourbar_redundant.case.yaml", output_dir=tmp_path)
    diagnostics = caught.value.diagnostics
    assert diagnostics, "InputError without diagnostics"
    text = "\n".join(f"{d.key}: {d.message}" for d in diagnostics)
    assert any(d.severity == "error" for d in diagnostics)
    assert "redundan" in text.lower(), text
    assert "rotation about" in text, text
    named = [joint for joint in LOOP_JOINTS if joint in text]
    assert named, f"no joint of the loop named in: {text}"
    # rows are examined joint by joint in definition order: the last joint of the loop is
    # the one whose equations repeat the others (thesis: "C: rotation about x, ...")
    messages = sorted(d.message for d in diagnostics)
    assert messages == sorted(
        f"redundant constraint: rocker_pivot: {direction}, dependent on crank_pivot, pin_b, pin_c"
        for direction in ("translation z", "rotation about x", "rotation about y")
    ), messages
    assert not list(tmp_path.iterdir()), "a refused run writes no result"


CASES = Path(__file__).resolve().parent / "cases"


def test_redundant_drop_runs_and_warns(run_case) -> None:
    """With `redundant: drop` the case runs; the warnings name what was dropped (a loop
    joint and a direction); the in-plane results, which do not depend on the dropped
    equations, match the planar references to 0.1% of their peaks."""
    outcome = run_case("fourbar_redundant_drop.case.yaml")
    warnings = "\n".join(all_warnings(outcome))
    assert warnings, "dropping redundant equations must be reported in the summary"
    assert any(joint in warnings for joint in LOOP_JOINTS), warnings
    th = _crank_rotation(outcome)
    assert_within_peak(
        channel(outcome, "drive_torque.value"),
        fourbar_drive_torque(th, FOURBAR),
        PEAK_FRACTION,
        "drive_torque.value",
    )
    loads = fourbar_static_loads(th, FOURBAR)
    peak = float(np.max(np.hypot(loads["crank_pivot_fx"], loads["crank_pivot_fy"])))
    for c in ("fx", "fy"):
        assert_within_peak(
            channel(outcome, f"crank_pivot_force.{c}"),
            loads[f"crank_pivot_{c}"],
            PEAK_FRACTION,
            f"crank_pivot_force.{c}",
            peak,
        )
