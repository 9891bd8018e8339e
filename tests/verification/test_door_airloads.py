"""Door airloads (thesis seed 000, 3.2.1-3.2.3): the 6-component wind tables in axes turning
with the door at the hinge line, and the aerodynamic damping while opening, against virtual
work in the kinematic opening (loadcases/library/door/opening.case.yaml)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import yaml
from conftest import estimate_off
from scipy.interpolate import Akima1DInterpolator

from loadcases.inputs.loader import load_case
from loadcases.run import run_case

DOOR = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "door"
DEG = np.pi / 180.0
# wind_mx of door.mech.yaml: the hinge moment (opening sense) vs opening angle
WIND_ANGLE = np.array([0.0, 30.0, 60.0, 90.0, 105.0]) * DEG
WIND_MX = np.array([0.0, 124.42, 186.63, 93.26, 41.85])  # N*m


def _opening(tmp_path: Path, name: str, **parameters: str) -> dict[str, np.ndarray]:
    """opening.case.yaml (kinematic, 4.8 s) with `parameters` set and the CB arm angle
    requested; its channels."""
    case = yaml.safe_load((DOOR / "opening.case.yaml").read_text(encoding="utf-8"))
    case["mechanism"] = str(DOOR / "door.mech.yaml")
    case["parameters"].update(parameters)
    case["requests"]["cb_angle"] = {"joint": "cb_pivot", "quantity": "angle"}
    path = tmp_path / f"{name}.case.yaml"
    path.write_text(yaml.safe_dump(case), encoding="utf-8")
    outcome = run_case(estimate_off(load_case(path)))
    assert outcome.solution.ok, outcome.solution.message
    return {"time": outcome.solution.time, **outcome.solution.channels}


def test_wind_hinge_moment_and_damping_by_virtual_work(tmp_path: Path) -> None:
    """The opening is kinematic, so two runs that differ by one load move alike and the CB
    handle's power differs by that load's power: dT_cb * dphi_cb/dt = -M * dtheta/dt.
    Wind: M = wind_mx at the opening angle (Akima, scipy, the hand value), the other five
    components acting on the hinge line (wind_centre on it within 1e-5 m) do no work; 1 %
    where the door turns (the rates are finite differences of the 0.05 s states). Damping:
    M = -c omega^2 / omega = -c theta_dot, c = 39 N*m*s/rad; 1 %."""
    calm = _opening(tmp_path, "calm", wind_sign="0", aero_damping="0 N*m*s/rad")
    wind = _opening(tmp_path, "wind", wind_sign="1", aero_damping="0 N*m*s/rad")
    damped = _opening(tmp_path, "damped", wind_sign="0", aero_damping="39 N*m*s/rad")
    t, theta = calm["time"], calm["hinge_angle.value"]
    assert np.allclose(wind["hinge_angle.value"], theta, atol=1e-9)
    theta_dot = np.gradient(theta, t)
    phi_dot = np.gradient(calm["cb_angle.value"], t)
    turning = (theta_dot > 0.1) & (t > 0.2) & (t < 4.6)
    assert turning.sum() > 40
    ratio = theta_dot[turning] / phi_dot[turning]
    d_wind = (wind["cb_torque.value"] - calm["cb_torque.value"])[turning]
    mx = Akima1DInterpolator(WIND_ANGLE, WIND_MX)(theta[turning])
    assert np.allclose(d_wind, -mx * ratio, rtol=0.01, atol=0.01 * mx.max())
    d_damped = (damped["cb_torque.value"] - calm["cb_torque.value"])[turning]
    assert np.allclose(d_damped, 39.0 * theta_dot[turning] * ratio, rtol=0.01)
    on_line = np.hypot(wind["wind_centre.y"] + 0.06, wind["wind_centre.z"])
    assert on_line.max() < 1e-5  # the lift 2 x 30 sin 55 deg = 49.149 mm given as 49.15
