"""IFToMM benchmark A05, the stiff flyball governor (issue 14 item 6).

Cases: loadcases/library/verification/hard/iftomm_a05_flyball.case.yaml (10 s, default
integrator and tolerance) and iftomm_a05_flyball_tight.case.yaml (generalized-alpha at
1e-9). The default suite runs their first 0.6 s, the default one without its accuracy
estimate (`accuracy: "off"`: the companion run costs 10 s of CPU on this stiff model); the
full 10 s, with the estimate, is opt-in (`pytest --long`).
Reference (tests/verification/flyball.py): no published time history could be obtained, so
an independent one, the hand-derived Lagrange equations in minimal coordinates solved by
scipy's LSODA at rtol 1e-11; and the benchmark's own invariants: the angular momentum about
the shaft is conserved, the energy falls by what the dampers dissipate (the `energy`
request's balance). Measured 2026-11-25, over 0.6 s, with the dense output of 0.7.0:
default travel 1.8e-4 of its peak, rod angle 1.6e-4, spin rate 1.4e-4, spring tension
7.4e-2 (with `output: steps`: 1.9e-4, 1.7e-4, 3.5e-5, 2.4e-2; the stiff damper's part:
above the 1e-3 acceptance; over 10 s the run's accuracy warning names it, 0.017); tight
1.5e-6, 1.4e-6, 9.1e-7, 4.8e-4 (1.6e-6, 1.5e-6, 3.0e-7, 1.4e-4 with `output: steps`).
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pytest
from flyball import D0, THETA0, Z0, flyball_energy, flyball_solve, spin_inertia, spring_tension
from references import all_warnings, channel

SHORT = 0.6  # s: the default suite's run, past the slider's first peak (0.5 s)
HARD = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification" / "hard"


def _run(tmp_path_factory, name: str, end: float, estimate: bool = True):
    """The hard case `name` run to `end` (s) (without the accuracy estimate unless
    `estimate`): it must finish."""
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case

    text = (HARD / name).read_text(encoding="utf-8").replace("end: 10.0", f"end: {end}")
    if not estimate and "accuracy:" not in text:
        text = text.replace("  step: 0.01\n", '  step: 0.01\n  accuracy: "off"\n')
    path = tmp_path_factory.mktemp("flyball") / name
    path.write_text(text.replace("mechanism: ", f"mechanism: {HARD}/"), encoding="utf-8")
    outcome = run_case(load_case(path))
    assert outcome.solution.status == "ok", outcome.solution.message
    assert outcome.solution.time[-1] == pytest.approx(end)
    return outcome


@pytest.fixture(scope="module")
def default(tmp_path_factory):
    return _run(tmp_path_factory, "iftomm_a05_flyball.case.yaml", SHORT, estimate=False)


@pytest.fixture(scope="module")
def tight(tmp_path_factory):
    return _run(tmp_path_factory, "iftomm_a05_flyball_tight.case.yaml", SHORT)


@cache
def _reference(times: tuple[float, ...]) -> np.ndarray:
    """The reference at `times` (s), solved once per grid."""
    return flyball_solve(np.array(times))


def _errors(outcome) -> dict[str, float]:
    """Largest error over the run of each quantity against the reference, of its peak."""
    ref = _reference(tuple(outcome.solution.time))
    pairs = {
        "travel": (channel(outcome, "travel.value"), ref[1] - Z0),
        "angle": (channel(outcome, "angle1.value"), ref[0] - THETA0),
        "spin": (channel(outcome, "spin_rate.value"), ref[2]),
        "tension": (channel(outcome, "spring1_force.value"), spring_tension(ref)),
    }
    return {k: float(np.max(np.abs(a - b)) / np.max(np.abs(b))) for k, (a, b) in pairs.items()}


def _momentum_drift(outcome) -> float:
    """Largest change of the angular momentum about the shaft, J(theta) psi', of its start."""
    theta = channel(outcome, "angle1.value") + THETA0
    momentum = spin_inertia(theta) * channel(outcome, "spin_rate.value")
    return float(np.max(np.abs(momentum - momentum[0])) / momentum[0])


@pytest.mark.parametrize(
    ("fixture", "bounds"),
    [
        ("default", {"travel": 4e-4, "angle": 4e-4, "spin": 2.8e-4, "tension": 0.15}),
        ("tight", {"travel": 3.5e-6, "angle": 3.5e-6, "spin": 1.8e-6, "tension": 1e-3}),
    ],
)
def test_motion_against_reference(request, fixture: str, bounds: dict[str, float]) -> None:
    """Over the first 0.6 s (the arms swing out, the slider travels 0.24 m and turns back)
    each quantity is within its bound of its peak against the minimal-coordinate reference
    (measured with the dense output of 0.7.0: default travel 1.8e-4, angle 1.6e-4, spin
    1.4e-4, tension 7.4e-2 (with `output: steps`: 1.9e-4, 1.7e-4, 3.5e-5, 2.4e-2); tight
    1.5e-6, 1.4e-6, 9.1e-7, 4.8e-4 (1.6e-6, 1.5e-6, 3.0e-7, 1.4e-4 with `output: steps`));
    the two arms move alike (to 1e-12 rad)."""
    outcome = request.getfixturevalue(fixture)
    errors = _errors(outcome)
    assert all(errors[k] < bounds[k] for k in bounds), errors
    assert np.max(channel(outcome, "travel.value")) > 0.2
    gap = channel(outcome, "angle1.value") - channel(outcome, "angle2.value")
    assert np.max(np.abs(gap)) < 1e-12


@pytest.mark.parametrize(
    ("fixture", "momentum", "balance"), [("default", 3e-4, 0.1), ("tight", 2e-6, 1.5e-3)]
)
def test_momentum_and_energy(request, fixture: str, momentum: float, balance: float) -> None:
    """No drift: the angular momentum about the shaft within `momentum` of its start (measured
    1.4e-4 default with the dense output of 0.7.0, 5.3e-5 with `output: steps`; 9.6e-7
    tight, 4.5e-7 with `output: steps`); the energy request's balance (T + V - W + D, 169 J
    at the start) within `balance` J (measured 0.048 J default, 0.015 J with `output:
    steps`; 7.6e-4 J tight, 4.7e-4 J with `output: steps`, where T + V itself matches the
    reference's to 1.3e-4 J). The dissipated energy grows and is within 30 % of the
    reference's E0 - E(0.6 s) = 2.4e-3 J (measured 15 % and 18 % low: the request sums the
    damper power by the trapezoid over the 0.01 s rows, and that power spikes within the
    damper's 7.5e-5 s time constant at the start)."""
    outcome = request.getfixturevalue(fixture)
    assert _momentum_drift(outcome) < momentum
    assert np.max(np.abs(channel(outcome, "energy.balance"))) < balance
    dissipated = channel(outcome, "energy.dissipated")
    assert np.all(np.diff(dissipated) >= 0.0)
    energy = flyball_energy(_reference(tuple(outcome.solution.time)))
    assert dissipated[-1] == pytest.approx(energy[0] - energy[-1], rel=0.3)
    assert channel(outcome, "spring1_force.length")[0] == pytest.approx(D0, abs=1e-9)


@pytest.mark.long
def test_ten_seconds(tmp_path_factory) -> None:
    """The case's full 10 s (ten swings of the arms, slowly damped) at the default settings
    with the accuracy estimate (10 s of CPU), and the tight setting (35 s): no failure;
    default travel within 6e-3 of its peak (measured 2.9e-3), angle 6e-3 (2.9e-3), spin
    1.2e-3 (6.3e-4), tension 0.1 (7.4e-2 with the dense output of 0.7.0 on, as over the
    first 0.6 s; 2.3e-2 with `output: steps`, measured 2026-11-25: above the 1e-3
    acceptance, and the run's accuracy warning names spring1_force); the tight run within
    4e-5 on the motion. Measured 2026-11-28 (0.10.0; 0.9.0 gives the same figures)."""
    default = _run(tmp_path_factory, "iftomm_a05_flyball.case.yaml", 10.0)
    errors = _errors(default)
    bounds = {"travel": 6e-3, "angle": 6e-3, "spin": 1.2e-3, "tension": 0.1}
    assert all(errors[k] < bounds[k] for k in bounds), errors
    warned = [w for w in all_warnings(default) if w.startswith("accuracy") and "histories" in w]
    assert warned and "spring1_force" in warned[0]
    tight = _errors(_run(tmp_path_factory, "iftomm_a05_flyball_tight.case.yaml", 10.0))
    assert max(tight["travel"], tight["angle"], tight["spin"]) < 4e-5, tight
