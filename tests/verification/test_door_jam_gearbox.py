"""Door library: jamming at the gearbox (thesis seed 000, sections 1.5.2, 4.2, 5.1.2,
appendix A figure 49) against the lever ratios of the spreadsheet. The gearbox output is
jammed (prescribed) and the ultimate load 1334 N acts on the inner handle grip (200 mm)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import estimate_off

from loadcases.inputs.loader import load_case
from loadcases.run import run_case

DOOR = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "door"


def _run(name: str):
    outcome = run_case(estimate_off(load_case(DOOR / name)))
    assert outcome.solution.ok, outcome.solution.message
    return outcome.solution.channels


def _xyz(ch, name):
    return np.column_stack([ch[f"{name}.{c}"] for c in "xyz"])


def _arm(ch, end, other, pivot):
    """Moment arm of the rod line (end -> other) about an axis through pivot along x."""
    a, b, p = _xyz(ch, end), _xyz(ch, other), _xyz(ch, pivot)
    u = (a - b) / np.linalg.norm(a - b, axis=1)[:, None]
    return np.linalg.norm(np.cross(a - p, u), axis=1)


@pytest.mark.parametrize(
    "name", ["jam_gearbox_no_gravity.case.yaml", "jam_gearbox_closing_no_gravity.case.yaml"]
)
def test_jammed_gearbox_rods_are_the_lever_ratios(name):
    """No gravity, handle load only. Rod P2P6 = F r_handle / (arm of P2P6 about the inner
    handle pivot); the jammed gearbox torque = rod P7P10 x (arm of P7P10 about the gearbox
    axis): the two cranks' statics, at every latch angle; tolerance 0.1 %. Opening and
    closing give the same rod force magnitudes and opposite gearbox torques."""
    ch = _run(name)
    p2p6 = 1334.0 * 0.200 / _arm(ch, "p2", "p6", "inner_pivot")
    assert np.allclose(ch["rod_p2p6.f"], p2p6, rtol=1e-3)
    gearbox = ch["rod_p7p10.f"] * _arm(ch, "p7", "p10", "gearbox_pt")
    assert np.allclose(np.abs(ch["gearbox_torque.value"]), gearbox, rtol=1e-3)
    sign = -1.0 if "closing" in name else 1.0
    assert np.all(sign * ch["gearbox_torque.value"] < 0)


def test_jammed_gearbox_p7p10_is_not_p2p6_times_the_latch_cranks():
    """The spreadsheet's chain F -> P2P6 -> latch shaft -> P7P10 (moment balance of the
    latch shaft about its axis with the two rods only) is not what the model gives: the
    handle load reaches the door through the inner handle pivot and the door pushes on the
    lift links, which are coupled to the latch shaft, so the latch shaft takes a third
    moment. Measured: P7P10 is 13 % above the chain at 0 deg and 15 % below it at 110 deg
    (no gravity); this test pins the difference (5 % .. 20 %) so a change shows."""
    ch = _run("jam_gearbox_no_gravity.case.yaml")
    chain = ch["rod_p2p6.f"] * _arm(ch, "p6", "p2", "latch_pt") / _arm(ch, "p10", "p7", "latch_pt")
    rel = ch["rod_p7p10.f"] / chain - 1.0
    assert 0.05 < np.max(np.abs(rel)) < 0.20
