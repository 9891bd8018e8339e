"""Door library: the handles (thesis seed 000, sections 1.5.1-1.5.2, 3.1.5.2, 3.2.1, 4.1-4.2,
5.1.2, figures 31, 32, 41-50) against hand statics and virtual work, the way the thesis'
spreadsheets did it: the outer-handle load with the gearbox jammed, the outer-handle jam in
the closing sense, lifting with the outer handle and with the jettison handle, and the
aerodynamic damping of the jettison."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import estimate_off

from loadcases.inputs.loader import load_case
from loadcases.run import run_case, run_file

DOOR = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "door"
HANDLE_LOAD = 1334.0  # N, ultimate handle load (thesis 4.2)


def _run(name: str, **overrides: float):
    outcome = run_case(estimate_off(load_case(DOOR / name, overrides=overrides or None)))
    assert outcome.solution.ok, outcome.solution.message
    return outcome.solution.channels


def _xyz(ch, name: str) -> np.ndarray:
    return np.column_stack([ch[f"{name}.{c}"] for c in "xyz"])


def _force(ch, name: str) -> np.ndarray:
    return np.column_stack([ch[f"{name}.f{c}"] for c in "xyz"])


def _moment(arm: np.ndarray, force: np.ndarray) -> np.ndarray:
    """Moment (N*m) about -x, the positive sense of every handle and shaft joint."""
    return -np.cross(arm, force)[:, 0]


def _arm(ch, end: str, other: str, pivot: str) -> np.ndarray:
    """Moment arm (m) of the rod line (end -> other) about an axis through pivot along x."""
    a, b, p = _xyz(ch, end), _xyz(ch, other), _xyz(ch, pivot)
    u = (a - b) / np.linalg.norm(a - b, axis=1)[:, None]
    return np.linalg.norm(np.cross(a - p, u), axis=1)


@pytest.fixture(scope="module")
def lifting_inner():
    return _run("lifting_inner.case.yaml")


def test_outer_load_with_the_gearbox_jammed_hand_statics():
    """Gearbox input jammed, 1334 N on the outer handle grip (150 mm), no gravity (thesis
    figures 31 and 50). Hand statics that hold to 1e-9 N*m (rigid bodies, no gravity):
    - gearbox (virtual work through the handle shaft, ratio 1, and the gear ratio 2): jam
      torque + handle torque 200.1 N*m + 2 x moment of rod P7P10 about the output axis = 0;
    - latch shaft: moment of P7P10 about the latch axis + moment of the fwd lower link's
      pin force about its pivot (coupler latch_drive, ratio 1) = 0: the rod carries the
      handle's pivot force that the door passes to the lift links;
    - rod P2P6 carries nothing (the inner handle is free).
    What does not agree: the spreadsheet's lever ratio P7P10 = (handle torque / 2) / arm of
    P7P10 about the output axis (2909 / 1667 / 2903 N at latch 0 / 55 / 110 deg) assumes the
    handle torque reaches the rod; here the jam between the handle and the gear train takes
    it, and P7P10 is 9-33 % of that (364 / 536 / 262 N measured); pinned at 5-40 %."""
    ch = _run("jam_gearbox_outer_no_gravity.case.yaml")
    handle = HANDLE_LOAD * 0.150
    rod = _force(ch, "rod_p7p10")  # on the rod from the latch shaft = on the gearbox from the rod
    output = _moment(_xyz(ch, "p7") - _xyz(ch, "gearbox_pt"), rod)
    assert np.allclose(ch["gearbox_torque.value"] + handle + 2.0 * output, 0.0, atol=1e-9)
    latch = _moment(_xyz(ch, "p10") - _xyz(ch, "latch_pt"), -rod)
    link = _moment(
        _xyz(ch, "lower_fwd_pin_pt") - _xyz(ch, "lower_fwd_pivot"), _force(ch, "lower_fwd_pin")
    )
    assert np.allclose(latch + link, 0.0, atol=1e-9)
    assert np.max(np.abs(latch)) > 5.0  # N*m: a real load path, not two zeros
    assert np.allclose(ch["rod_p2p6.f"], 0.0, atol=1e-6)
    sheet = handle / 2.0 / _arm(ch, "p7", "p10", "gearbox_pt")
    share = ch["rod_p7p10.f"] / sheet
    assert share.min() > 0.05 and share.max() < 0.40


def test_outer_handle_jam_closing_is_the_lever_ratio():
    """Outer handle jammed, 1334 N on the inner handle in the closing sense, no gravity:
    rod P2P6 = F r_handle / (arm of P2P6 about the inner handle pivot), as the lifting sense
    (test_door_statics); source: statics of the handle; tolerance 0.1 %."""
    ch = _run("jam_outer_handle_closing_no_gravity.case.yaml")
    expected = HANDLE_LOAD * 0.200 / _arm(ch, "p2", "p6", "inner_pivot")
    assert np.allclose(ch["rod_p2p6.f"], expected, rtol=1e-3)


def test_lifting_with_the_outer_handle_by_virtual_work(lifting_inner, tmp_path):
    """Lifting with the outer handle, no pressure: the outer handle turns 55 deg for the
    inner handle's 110 deg (gearbox ratio 2, both rod parallelograms 1:1) through the same
    states, so by virtual work T_outer = 2 T_inner at every latch angle (1e-6); the handle
    force is T_outer / 0.15 m. Run with the contacts on: the jettison lever never touches
    the roller (the roller moves away from it), so the jettison handle changes nothing."""
    text = (DOOR / "lifting_outer.case.yaml").read_text(encoding="utf-8")
    text = text.replace("mechanism: door.mech.yaml", f"mechanism: {DOOR / 'door.mech.yaml'}")
    text = text.replace("effects: {contact: false}", "effects: {contact: true}")
    text = text.replace(
        "abscissa:", "  jettison_lever: {contact: jettison_lever, quantity: force}\nabscissa:"
    )
    path = tmp_path / "lifting_outer_contact.case.yaml"
    path.write_text(text, encoding="utf-8")
    solution = run_file(path, output_dir=tmp_path / "out")[0].solution
    assert solution.ok, solution.message
    ch = solution.channels
    inner = lifting_inner  # the same output times (0.05 s)
    assert np.allclose(ch["latch_angle.value"], inner["latch_angle.value"], atol=1e-9)
    assert np.allclose(ch["handle_torque.value"], 2.0 * inner["handle_torque.value"], rtol=1e-6)
    assert np.allclose(ch["handle_force.value"], ch["handle_torque.value"] / 0.15, rtol=1e-9)
    assert np.all(ch["jettison_lever.normal"] == 0.0)


def test_jettison_handle_effort_by_the_lever_geometry(lifting_inner):
    """Lifting with the jettison handle, no pressure. Statics of the jettison handle (its
    weight acts on its pivot): effort = the moment about the jettison axis with which the
    roller resists the lever (1e-6). The roller's crank circle passes through the jettison
    pivot, so the lever turns half the inner handle angle (inscribed angle): latch = 2 x
    jettison angle within 0.5 deg (the roller lags by the 0.2 mm design gap and the
    0.07 mm contact penetration over its 50 mm crank). By virtual work the lever torque is
    twice the inner handle torque at the same latch angle: within 1 % (0.16 % measured away
    from the contact hand-overs at about 5, 33 and 71-77 deg of latch, where interpolating
    the inner lifting's 5.5 deg states adds up to 0.84 %). Without the airload, as the inner
    lifting."""
    ch = _run("lifting_jettison.case.yaml", jettison_on=0.0)
    on_roller = _force(ch, "roller")
    lever = _moment(_xyz(ch, "roller_point") - _xyz(ch, "jettison_pivot"), -on_roller)
    effort = ch["handle_torque.value"]
    assert np.allclose(effort, -lever, rtol=1e-6, atol=1e-6)
    # at rest on the latch down-stop the roller is 0.2 mm clear; in contact over the lift
    assert ch["roller.normal"][0] == 0.0 and np.all(ch["roller.normal"][1:] > 300.0)
    theta, psi = ch["latch_angle.value"], ch["jettison_angle.value"]
    assert np.allclose(theta, 2.0 * psi, atol=np.radians(0.5))
    lifted = theta > 0.0  # the first state sits 0.32 deg below the inner lifting's data
    inner = np.interp(
        theta[lifted], lifting_inner["latch_angle.value"], lifting_inner["handle_torque.value"]
    )
    assert np.allclose(effort[lifted], 2.0 * inner, rtol=1e-2)
    assert np.allclose(ch["handle_force.value"], ch["handle_torque.value"] / 0.25, rtol=1e-9)


def test_aerodynamic_damping_takes_the_power_c_omega_squared():
    """Jettison with aero_damping c = 187 N*m*s/rad: the damping force at the centre of
    airload takes the power F.v = -c omega^2 (omega the hinge rate; latch held, so the door
    turns with the yoke), i.e. it is a moment c omega opposing the hinge rotation; 1e-6
    where omega > 0.1 rad/s. Source: thesis 3.2.1, F = c omega / l_coa."""
    ch = _run("jettison.case.yaml")
    omega = ch["hinge_rate.value"]
    power = np.sum(_force(ch, "aero_damper") * _xyz(ch, "coa_velocity"), axis=1)
    moving = np.abs(omega) > 0.1
    assert moving.sum() > 50
    assert np.allclose(power[moving], -187.0 * omega[moving] ** 2, rtol=1e-6)
    tangential = np.hypot(ch["top_velocity.y"], ch["top_velocity.z"])  # 1 m from the line
    assert np.allclose(np.abs(omega), tangential, rtol=1e-6, atol=1e-9)
