"""BepiColombo-MPO-like wing of the solar-array library (loadcases/library/solar_array/):
cross-checks of the seed-003 items against closed forms.

- latch-spring tuning (appendix A): mode 2 of the held two-panel model hits 4.1672 Hz
  within 1e-4 Hz (measured < 1e-8); the stiffness equals the exact 2 x 2 eigenvalue
  solution within 1e-6 (measured ~1e-9) and the appendix's 19.344 N*m/deg within 1e-4;
- torque margin (eq. 2.1) at 0, 90, 180 deg by hand (in orbit the pin carries no radial
  load: friction = T_pret), 1e-9 relative;
- energy over the deployment with the SADM held: spring energy released = kinetic +
  friction work, 1 % (measured 5e-5);
- latch-up peak with the SADM held: K theta_max from 1/2 I w^2 + T theta = 1/2 K theta^2
  (the one-DOF estimate w sqrt(I K) plus the drive torque at latch), 1 % (measured 1.8e-4);
- in orbit, no external load but the SADM: the interface impulse equals the change of the
  wing's linear momentum through a latch-up where the SADM slips, 1 % of the largest
  momentum (measured 5e-5; trapezoidal impulse at 1 ms).
Runs are shortened copies of the library cases (coarser output, ends before 6.24 s).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import LIBRARY, solve_case

WING = LIBRARY.parent / "solar_array"
DEG = math.pi / 180
K_DEPLOY, WINDUP, T_PRET_HOT = 0.3, 400 * DEG, 0.05
D2 = 0.9**2 + 0.015**2  # squared distance of each panel's cm from HL2, m^2
I_IN, I_OUT = 2.2862 + 8.4658 * D2, 1.2503 + 4.63 * D2  # about HL2 (mechanism file)


def _harness(theta):
    return np.interp(theta, [0, math.pi / 2, math.pi], [0.15, 0.05, -0.05])


def _harness_work(theta: float) -> float:
    """Integral of the harness moment from 0 to theta (linear table, exact)."""
    grid = np.linspace(0.0, theta, 20001)
    return float(np.trapezoid(_harness(grid), grid))


def _variant(tmp_path: Path, name: str, edits: dict[str, str]) -> Path:
    text = (
        (WING / name)
        .read_text()
        .replace("mechanism: bepicolombo.mech.yaml", f"mechanism: {WING / 'bepicolombo.mech.yaml'}")
    )
    for old, new in edits.items():
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / name
    path.write_text(text)
    return path


def test_latch_tuning_reproduces_appendix() -> None:
    from loadcases.studies.tune import tune_parameter

    result = tune_parameter(
        WING / "bepicolombo_latch_tuning.case.yaml", parameter="k_latch", mode=2, target=4.1672
    )
    assert abs(result.frequency - 4.1672) < 1e-4
    w2, k0 = (2 * math.pi * 4.1672) ** 2, 1e-3  # k0: the soft hold of the rigid mode
    # det(K - w2 M) = 0 for K = [[k0 + 2k, -2k], [-2k, 2k]], M = diag(I_in, I_out)
    two_k = (k0 - w2 * I_IN) * w2 * I_OUT / (k0 - w2 * (I_IN + I_OUT))
    assert result.value == pytest.approx(two_k / 2, rel=1e-6)
    assert result.value * DEG == pytest.approx(19.344, rel=1e-4)


def test_torque_margin_by_hand() -> None:
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    outcome = run_case(load_case(WING / "bepicolombo_tm_cold.case.yaml"))
    ch = outcome.solution.channels
    for angle in (0.0, 90.0, 180.0):
        i = int(np.argmin(np.abs(ch["tm_HL2.angle"] - angle * DEG)))
        theta = ch["tm_HL2.angle"][i]
        h = float(_harness(theta))
        driving = K_DEPLOY * (WINDUP - theta) + max(0.0, -h)
        resistive = 1.5 * 0.1 + 3.0 * max(0.0, h) + 1.5 * 2.0 * math.pi / 60
        assert ch["tm_HL2.ratio"][i] == pytest.approx(driving / resistive, rel=1e-9)
    line = outcome.checks["torque_margin"]["hinge_lines"]["HL2"]
    assert line["angle_of_min"] == pytest.approx(0.0, abs=1e-12)
    assert line["min_ratio"] == pytest.approx(2.0944 / 0.75708, rel=1e-4) and line["passed"]


@pytest.fixture(scope="module")
def held(tmp_path_factory):
    """Hot deployment with the SADM held (holding torque 1e4 N*m), to 3 s (before latch)."""
    path = _variant(
        tmp_path_factory.mktemp("held"),
        "bepicolombo_deploy_hot.case.yaml",
        {"end: 6.24, step: 0.002": "end: 3.0, step: 0.01"},
    )
    return solve_case(path, sadm_holding=1.0e4)


def test_energy_balance(held) -> None:
    ch, t = held.channels, held.time
    theta, omega = ch["hl2_angle.value"], ch["hl2_rate.value"]
    assert np.abs(ch["sadm_angle.value"]).max() < 1e-9
    springs = K_DEPLOY * (WINDUP * theta - theta**2 / 2) - _harness_work(theta[-1])
    friction = np.trapezoid(np.abs(ch["hl2_friction.value"] * omega), t)
    kinetic = 0.5 * I_OUT * omega[-1] ** 2
    assert kinetic + friction == pytest.approx(springs[-1], rel=1e-2)
    # measured 2.4e-4 with the dense output of 0.7.0 (5e-5 with `output: steps`)
    assert kinetic + friction == pytest.approx(springs[-1], rel=5e-4)


def test_latch_peak_one_dof(tmp_path) -> None:
    """Start at 179 deg with the hot run's rate; K = 2 k_latch, I = I_out (SADM held)."""
    w0 = 1.3594
    path = _variant(
        tmp_path,
        "bepicolombo_deploy_hot.case.yaml",
        {
            "end: 6.24, step: 0.002": "end: 0.2, step: 0.0005",
            "hl2: {value: 0, rate: 0}": f"hl2: {{value: 179 deg, rate: {w0} rad/s}}",
        },
    )
    sol = solve_case(path, sadm_holding=1.0e4)
    k = 2 * 19.344 / DEG
    drive = K_DEPLOY * (WINDUP - math.pi) - T_PRET_HOT + 0.05  # spring - friction + harness
    w = math.sqrt(w0**2 + 2 * DEG * (K_DEPLOY * (WINDUP - math.pi) - T_PRET_HOT) / I_OUT)
    peak = drive + math.sqrt(drive**2 + k * I_OUT * w**2)
    assert sol.channels["latch_torque.value"].max() == pytest.approx(peak, rel=1e-2)
    assert sol.channels["latch_torque.value"].max() == pytest.approx(peak, rel=1e-3)  # 1.8e-4


def test_in_orbit_momentum(tmp_path) -> None:
    """From 170 deg at the hot run's rate through the latch-up, where the SADM slips past
    its holding torque: impulse of the SADM reaction over 0.4 s = change of momentum."""
    path = _variant(
        tmp_path,
        "bepicolombo_deploy_hot.case.yaml",
        {
            "end: 6.24, step: 0.002": "end: 0.4, step: 0.001",
            "hl2: {value: 0, rate: 0}": "hl2: {value: 170 deg, rate: 1.33 rad/s}",
        },
    )
    sol = solve_case(path)
    ch, t = sol.channels, sol.time
    assert np.ptp(ch["sadm_angle.value"]) > 0.05  # the SADM did slip
    impulse = np.array([np.trapezoid(ch[f"sadm_force.f{c}"], t) for c in "xy"])
    momentum = np.array(
        [
            8.4658 * ch[f"inboard_cm_velocity.{c}"] + 4.63 * ch[f"outboard_cm_velocity.{c}"]
            for c in "xy"
        ]
    )
    change = momentum[:, -1] - momentum[:, 0]
    scale = np.abs(momentum).max()
    assert np.abs(impulse - change).max() < 1e-2 * scale
    # measured 4.8e-4 with the dense output of 0.7.0 (5e-5 with `output: steps`; trapezoid, 1 ms)
    assert np.abs(impulse - change).max() < 1e-3 * scale


def test_library_files_validate() -> None:
    """Every file of the solar-array library validates and every case builds (as `loads
    validate` and the set's pre-build do), without warnings."""
    from loadcases.inputs.loader import validate_files
    from loadcases.run import check_case_file

    files = sorted(WING.glob("*.yaml"))
    assert len(files) >= 5
    assert validate_files(files) == []
    for case in WING.glob("*.case.yaml"):
        assert check_case_file(case) == [], case.name
