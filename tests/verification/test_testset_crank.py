"""Simeon's flexible slider-crank (issue 35 item 5): a flexible body started deformed, against
the published solution of the Test Set for IVP Solvers, problem `crank`.

Case: loadcases/library/verification/hard/testset_crank.case.yaml (+ .mech.yaml): the rod
is 8 Timoshenko beam elements reduced on its ends and quarter points; it starts from the test
set's initial values (INIT) given as the rod's modal coordinates and rates.
Reference: the test set's solution at t = 0.1 s (SOLN; tests/verification/testset_crank.py).
The test set's coordinates are read from the positions of the rod's five interface points:
the chord from the crank pin to the slider pin is its rod axis (phi2, q4), the lateral
displacements at the quarter points give q1 and q2, the axial one at the middle q3.
Acceptance: 2 % of each published value (the issue's done-when); the rigid coordinates to
1e-5. The case runs at tolerance 1e-8: at the default 1e-6 the axial coordinates carry the
time integration's error, and which sequence of steps the step control takes decides it
(measured 2026-11-29: a relative change of 1e-12 in one initial mode moves q3 and q4 from
-0.53/-0.17 % to +1.54/+2.07 % or -1.74/-1.47 %; the compiled flexible kernels, equal to the
Python formulas to 3e-16, tests/mechlib/test_flexible_kernels.py, took another sequence,
-2.9/-2.7 %). At 1e-8 the same change moves them by 0.05 %. Measured at 1e-8 (generalized-
alpha, 9740 steps, 1823 rejected, 18 s of CPU): phi2 2.6e-7, x3 4.6e-7, q1 7.0e-3, q2
1.11e-2, q3 5.6e-3, q4 8.9e-3: the models' difference: the test set's axial mass is
15 times its element's consistent one (moving q3 and q4 at 0.1 s by 0.8 % and 0.7 % in the
test set's own equations), its lateral deflection two sines, the engine's a beam.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml
from testset_crank import L1, L2, V0, Y0, Y_END, chord_coordinates, equations, shape

HARD = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification" / "hard"
CASE = HARD / "testset_crank.case.yaml"
POINTS = ("a", "quarter", "middle", "three_quarter", "b")


def _published_as_modes(component) -> tuple[np.ndarray, np.ndarray]:
    """The test set's initial q and q' as the rod's modal coordinates and rates: each
    interface node's displacement (axial, lateral) and rotation (the slope) from the test
    set's shape functions, fitted by the modes and the six rigid motions (least squares;
    30 equations, 24 + 6 unknowns here: exact)."""
    k, n = len(component.node_ids), component.count
    basis = np.concatenate([component.phi, component.phi_star], axis=1).reshape(6 * k, n)
    rigid = np.zeros((k, 6, 6))
    fields = []
    for p, s in enumerate(component.positions):
        rigid[p, :3, :3] = rigid[p, 3:, 3:] = np.eye(3)
        rigid[p, :3, 3:] = [[0, s[2], -s[1]], [-s[2], 0, s[0]], [s[1], -s[0], 0]]  # -skew(s)
        xi = (component.origin[0] + s[0] - L1) / L2
        axial, lateral, slope = shape(xi)
        fields.append(np.array([axial, lateral, 0 * axial, 0 * axial, 0 * axial, slope]))
    system = np.hstack([basis, rigid.reshape(6 * k, 6)])
    nodal = np.concatenate(fields)  # (6 k, 4): per unit q1..q4
    wanted = nodal @ np.c_[Y0[3:], V0[3:]]
    solved, *_ = np.linalg.lstsq(system, wanted, rcond=None)
    assert np.abs(system @ solved - wanted).max() < 1e-12 * np.abs(wanted).max()
    return solved[:n, 0], solved[:n, 1]


def _coordinates(solution, row: int) -> np.ndarray:
    """phi2, x3, q1..q4 at output row `row` from the interface points' positions."""
    channels = solution.channels
    at = [[channels[f"{p}.x"][row], channels[f"{p}.y"][row]] for p in POINTS]
    return chord_coordinates(*at)


def test_the_case_starts_from_the_published_initial_values() -> None:
    """The case's `modes` and `rates` are the published initial values projected on the
    rod's modes as built (1e-9 of the largest; the case writes round-off as 0): a change of
    the reduction that changed the modes' shapes fails here, not silently in the run."""
    from loadcases.build.model import build_run
    from loadcases.inputs.loader import load_case

    built = build_run(load_case(CASE))
    modes, rates = _published_as_modes(built.mechanism.flexible["rod"].component)
    given = yaml.safe_load(CASE.read_text("utf-8"))["initial"]["rod"]
    assert np.abs(np.array(given["modes"]) - modes).max() < 1e-9 * np.abs(modes).max()
    assert np.abs(np.array(given["rates"]) - rates).max() < 1e-9 * np.abs(rates).max()


@pytest.mark.slow
def test_published_solution_at_0_1_s() -> None:
    """At t = 0 the run's coordinates are the published ones (1e-9: the assembly kept the
    given modes and met the constraints with them); at 0.1 s each within 2 % (measured:
    module docstring)."""
    from conftest import solve_case

    solution = solve_case(CASE)
    start = _coordinates(solution, 0)
    assert np.abs(start - Y0[1:]).max() < 1e-9
    assert solution.time[-1] == pytest.approx(0.1)
    end = _coordinates(solution, -1)
    assert solution.channels["crank_angle.value"][-1] == pytest.approx(Y_END[0])
    assert end[:2] == pytest.approx(Y_END[1:3], rel=1e-5)
    assert end[2:] == pytest.approx(Y_END[3:], rel=2e-2)


@pytest.mark.long
def test_the_transcription_reproduces_the_published_solution() -> None:
    """The reference's own check: testset_crank.equations (index 1) integrated by DOP853 at
    rtol 1e-11 from INIT reproduces SOLN to 1e-5 (measured 3.6e-6 on q4; 72 s of CPU)."""
    from scipy.integrate import solve_ivp

    run = solve_ivp(equations(), (0, 0.1), np.r_[Y0, V0], method="DOP853", rtol=1e-11, atol=1e-13)
    assert run.y[:7, -1] == pytest.approx(Y_END, rel=1e-5)


def test_the_quasi_static_start_is_the_published_one(tmp_path: Path) -> None:
    """`deformed: static` instead of the published modes: the engine's own quasi-static
    deflection at t = 0 (the slider's and the rod's inertia at 150 rad/s, no bending then)
    is the test set's initial axial deflection, INIT's q3 and q4 "close to smooth motion",
    within 1e-3 (measured 6.6e-5 and 8.3e-5), unbent (q1, q2 below 1e-12 m)."""
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    case = yaml.safe_load(CASE.read_text("utf-8"))
    case["initial"] = {"rod": {"deformed": "static"}}
    case["analysis"] = {"type": "dynamic", "end": 1e-4, "step": 1e-4, "accuracy": "off"}
    mech = HARD / case["mechanism"]
    (tmp_path / mech.name).write_text(mech.read_text("utf-8"), "utf-8")
    (tmp_path / "static.case.yaml").write_text(yaml.safe_dump(case), "utf-8")
    solution = run_case(load_case(tmp_path / "static.case.yaml")).solution
    start = _coordinates(solution, 0)
    assert start[4:] == pytest.approx(Y0[5:], rel=1e-3)
    assert np.abs(start[2:4]).max() < 1e-12
    assert start[1] == pytest.approx(Y0[2], rel=1e-8)
