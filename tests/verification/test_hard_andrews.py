"""Andrews' squeezing mechanism (issue 14 item 6): a published index-3 benchmark in CI.

Cases: loadcases/library/verification/hard/andrews_squeezer.case.yaml (default integrator
and tolerance) and andrews_squeezer_tight.case.yaml (Radau IIA at tolerance 3e-7).
Reference: the Test Set for IVP Solvers, problem `andrews` (PSIDE at 1e-14): coordinates,
rates and multipliers at t = 0.03 s, and the consistent initial multipliers
(tests/verification/andrews.py). Acceptance: 1e-3 of each request's peak over the run.
Measured 2026-11-25 (default, dense output of 0.7.0): angles 7.4e-4 of their peak (met),
rates 1.6e-2 (missed: the run's accuracy warning says so), reaction at E 3.8e-3 (with
`output: steps`: 6.1e-4, 1.3e-2, 3.1e-3); tight (dense): angles 2.0e-8 of their peak, rates
4.4e-7, reaction at E 9.7e-8 (with `output: steps`: 3.7e-8, 8.1e-7, 1.8e-7).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml
from andrews import JOINTS, LAMBDA0, LAMBDA_END, NAMES, Q0, Q_END, V_END, loop_points, loop_residual
from references import all_warnings, channel

HARD = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification" / "hard"
ACCEPTANCE = 1e-3  # of each request's peak: the sizing accuracy (DEFAULT_ACCURACY)


@pytest.fixture(scope="module")
def default(run_case):
    return run_case("hard/andrews_squeezer.case.yaml")


@pytest.fixture(scope="module")
def tight(run_case):
    return run_case("hard/andrews_squeezer_tight.case.yaml")


def _coordinates(outcome) -> np.ndarray:
    """The test set's seven coordinates per output row (rad), from the expression requests."""
    return np.stack([channel(outcome, f"{name}.value") for name in NAMES], axis=1)


def _rates(outcome) -> np.ndarray:
    """Their rates per output row (rad/s), from the joint `omega` requests."""
    return np.stack([channel(outcome, f"{name}_rate.value") for name in NAMES], axis=1)


def _end_errors(outcome) -> tuple[np.ndarray, np.ndarray]:
    """Error at t = 0.03 s of each coordinate and rate, relative to its peak |value|."""
    q, v = _coordinates(outcome), _rates(outcome)
    q_error = np.abs(q[-1] - Q_END) / np.max(np.abs(q), axis=0)
    v_error = np.abs(v[-1] - V_END) / np.max(np.abs(v), axis=0)
    return q_error, v_error


def _reaction_error(outcome) -> float:
    """Error at t = 0.03 s of the reaction at E (on k2 from k3 = -lambda), of its peak |f|."""
    force = np.array([channel(outcome, "E_force.fx")[-1], channel(outcome, "E_force.fy")[-1]])
    return float(np.max(np.abs(force + LAMBDA_END)) / np.max(channel(outcome, "E_force.f")))


def test_case_file_is_the_loop_closure() -> None:
    """The mechanism file's joints, spring ends and centres of mass are the test set's loop
    closed at its initial state (1e-15 m: the file holds them to 17 digits); the published
    initial state and reference close the loop to round-off (1e-15 m)."""
    mech = yaml.safe_load((HARD / "andrews_squeezer.mech.yaml").read_text(encoding="utf-8"))
    p = loop_points(Q0)
    joints = {"o": "O", "f": "F", "b": "B", "a5": "A", "g": "G", "a7": "A", "h": "H"}
    joints |= {"e3": "E2", "e4": "E2", "e6": "E2"}
    for joint, point in joints.items():
        assert np.allclose(mech["joints"][joint]["at"][:2], p[point], rtol=0, atol=1e-15), joint
    for name in ("D", "C", "E"):
        at = mech["points"][name]["at"][:2]
        assert np.allclose(at, p["E2" if name == "E" else name], rtol=0, atol=1e-15), name
    for k in range(1, 8):
        cm = mech["bodies"][f"k{k}"]["cm"][:2]
        assert np.allclose(cm, p[f"cm{k}"], rtol=0, atol=1e-15), f"k{k}"
    for joint, name in zip(JOINTS, NAMES):
        assert mech["joints"][joint]["type"] == "revolute"
        assert mech["parameters"][f"{name}0"] == pytest.approx(Q0[NAMES.index(name)], abs=1e-17)
    assert loop_residual(Q0) < 1e-15 and loop_residual(Q_END) < 1e-15


@pytest.mark.parametrize("fixture", ["default", "tight"])
def test_initial_reaction_is_the_published_multiplier(request, fixture: str) -> None:
    """At t = 0 the reaction at E on k2 from k3 is minus the test set's consistent initial
    multipliers (98.567, -6.123) N within 1e-9 relative (measured 1e-15): the masses, inertias,
    spring and torque give the published accelerations before any integration."""
    outcome = request.getfixturevalue(fixture)
    force = np.array([channel(outcome, "E_force.fx")[0], channel(outcome, "E_force.fy")[0]])
    assert np.max(np.abs(force + LAMBDA0)) < 1e-9 * np.linalg.norm(LAMBDA0)


def test_default_angles_meet_the_acceptance(default) -> None:
    """Default settings: every coordinate at t = 0.03 s within 1e-3 of its peak (the
    acceptance; measured 7.4e-4 with dense output, 6.1e-4 with `output: steps`, Theta after
    2.5 turns of the crank)."""
    assert channel(default, "beta.value").shape == (101,)
    q_error, _ = _end_errors(default)
    assert np.max(q_error) < ACCEPTANCE, dict(zip(NAMES, q_error))


def test_default_rates_miss_the_acceptance_and_say_so(default) -> None:
    """Default settings: the rates at t = 0.03 s are within 2.6e-2 of their peak (measured
    1.6e-2 with dense output, 1.3e-2 with `output: steps`, for gamma, Phi and Omega: above
    the 1e-3 acceptance) and the reaction at E within 6e-3 (measured 3.8e-3; 3.1e-3). The
    run does not hide it: its accuracy block says the target is not met and a warning names
    the rates whose time histories miss it; the estimate of each coordinate and rate is at
    least 2/3 of the error found against the reference."""
    q_error, v_error = _end_errors(default)
    assert np.max(v_error) < 2.6e-2, dict(zip(NAMES, v_error))
    assert _reaction_error(default) < 6e-3
    block = default.checks["accuracy"]
    assert block["met"] is False and block["target"] == ACCEPTANCE
    warned = [w for w in all_warnings(default) if w.startswith("accuracy") and "histories" in w]
    assert warned and all(f"{name}_rate" in warned[0] for name in ("gamma", "Phi", "Omega"))
    for name, q_err, v_err in zip(NAMES, q_error, v_error):
        assert q_err <= 1.5 * block["estimate"][name]["history"], name
        assert v_err <= 1.5 * block["estimate"][f"{name}_rate"]["history"], name


def test_tight_setting_reaches_1e6(tight) -> None:
    """Radau IIA at tolerance 3e-7: coordinates within 5e-8 relative of the reference
    (the issue asks 1e-6; measured 1.4e-8), rates within 5e-7 of their peak (the issue's
    1e-6; measured 1.0e-7 with the packages of 2026-11-28, 3.4e-7 for gamma with scipy 1.17.1
    and numpy 2.4.6 on 2026-11-29, the same before and after mechlib's move into packages),
    the reaction at E within 2.5e-7 of its peak (measured 8.3e-8). Radau's step sequence
    here moves with round-off alone: at tolerance 1e-6 the rates were 4.4e-7 to 2.3e-6
    depending on the BLAS's threads (one since version 0.10.0,
    loadcases.foundation.process_settings), and 1e-7 gives no smaller error (measured 1.2e-7 in the
    coordinates): the projection onto the constraints at each output time, not the
    tolerance, bounds it."""
    q = _coordinates(tight)
    assert np.max(np.abs(q[-1] - Q_END) / np.abs(Q_END)) < 5e-8
    _, v_error = _end_errors(tight)
    assert np.max(v_error) < 5e-7, dict(zip(NAMES, v_error))
    assert _reaction_error(tight) < 2.5e-7


@pytest.mark.parametrize(("fixture", "bound"), [("default", 1e-11), ("tight", 1e-14)])
def test_loop_stays_closed(request, fixture: str, bound: float) -> None:
    """The seven coordinates close the three loops at every output row: the four positions
    of E agree within `bound` m (measured 4e-13 m default, 6e-17 m tight; the mechanism is
    0.1 m across), and the run ends at 0.03 s without a solver failure."""
    outcome = request.getfixturevalue(fixture)
    assert outcome.solution.status == "ok"
    assert outcome.solution.time[-1] == pytest.approx(0.03)
    assert max(loop_residual(q) for q in _coordinates(outcome)) < bound
