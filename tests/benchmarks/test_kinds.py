"""The bench models of other kinds (benchmarks/kinds): one spec, the same motion in both codes.

Each model is built for both codes and run over a short horizon; Exudyn at a fine fixed
step must land on `loads` at a tight tolerance within a loose bound (the differences left
are the stated ones: switching at step boundaries, a valve held over a step, both of first
order in Exudyn's step). Closed forms check what each model rests on: the spool's step
response, the flaps' free fall to their latch angles, the ball's flight to the socket wall.
No test here measures time. Skipped without Exudyn where Exudyn is needed.
"""

from __future__ import annotations

import importlib.util
import math
import tempfile
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from benchmarks.accuracy import Reference, relative_error
from benchmarks.cases import case_path, case_yaml
from benchmarks.exudyn_models import ExudynOptions, run_exudyn
from benchmarks.kinds import hydraulic, kind_models, latch, socket
from benchmarks.models import GRAVITY, ModelSpec, degrees_of_freedom, model_by_name
from benchmarks.suite import _case_copy

needs_exudyn = pytest.mark.skipif(
    importlib.util.find_spec("exudyn") is None,
    reason="Exudyn not installed (pip install -e '.[bench]')",
)

KINDS = [m.name for m in kind_models()]


def _loads(model: ModelSpec, end: float, tolerance: float):
    from loadcases.run import run_file

    with tempfile.TemporaryDirectory() as tmp:
        case = _case_copy(model, end, tolerance, Path(tmp), "steps")
        solution = run_file(case, output_dir=Path(tmp) / "out")[0].solution
    assert solution.ok, solution.message
    return solution


def _as_reference(model: ModelSpec, solution) -> Reference:
    channels = {c: np.asarray(solution.channels[c], dtype=float) for c in model.main}
    return Reference(model.name, np.asarray(solution.time, dtype=float), channels, {})


@pytest.mark.parametrize("name", KINDS)
def test_committed_case_file_matches_the_spec(name: str) -> None:
    model = model_by_name(name)
    assert case_path(model).read_text(encoding="utf-8") == case_yaml(model), (
        "run `python -m benchmarks.cases` to regenerate the case files"
    )


@pytest.mark.parametrize(
    "name, dof",
    [("socket_rattle", 6), ("flap_latches", 3), ("fourbar_friction", 1), ("hydraulic_ram", 1)],
)
def test_mobility(name: str, dof: int) -> None:
    assert degrees_of_freedom(model_by_name(name)) == (dof, 0)


#: (horizon s, loads tolerance, Exudyn step s, bound on the relative error): horizons
#: covering each model's first contacts, first latch, reversals and valve opening; bounds
#: about twice the errors measured on 2026-11-29 (6.3e-5, 2.4e-5, 2.3e-5, 7.0e-4: Exudyn's
#: own error at these steps, first order in the step for its switched latch and valve).
SHORT_RUNS = {
    "socket_rattle": (0.02, 1e-10, 1e-6, 1.5e-4),
    "flap_latches": (0.35, 1e-9, 2.5e-5, 5e-5),
    "fourbar_friction": (0.5, 1e-9, 2.5e-4, 5e-5),
    "hydraulic_ram": (0.03, 1e-9, 2.5e-5, 1.5e-3),
}


@needs_exudyn
@pytest.mark.parametrize("name", KINDS)
def test_both_codes_produce_the_same_motion(name: str) -> None:
    """Exudyn at a fine fixed step lands on `loads` at a tight tolerance (SHORT_RUNS)."""
    model = model_by_name(name)
    end, tolerance, step, bound = SHORT_RUNS[name]
    solution = _loads(model, end, tolerance)
    run = run_exudyn(
        model,
        ExudynOptions(step=step, end=end, output_step=model.output_step, linear_solver="sparse"),
    )
    moved = max(np.ptp(solution.channels[c]) for c in model.main)
    assert moved > 0.0
    error = relative_error(run.time, run.channels, _as_reference(model, solution), model.main)
    assert error < bound


def test_spool_opening_is_the_second_order_step_response() -> None:
    """Against x'' + 2 zeta w x' + w^2 x = w^2 from rest, integrated by SciPy (rtol 1e-10)."""
    w, z = 2.0 * math.pi * hydraulic.VALVE_FREQUENCY, hydraulic.VALVE_DAMPING
    t = np.linspace(0.0, 0.05, 201)
    ode = solve_ivp(
        lambda _t, y: [y[1], w * w * (1.0 - y[0]) - 2.0 * z * w * y[1]],
        (0.0, t[-1]),
        [0.0, 0.0],
        t_eval=t,
        rtol=1e-10,
        atol=1e-12,
    )
    assert np.max(np.abs(ode.y[0] - [hydraulic.spool_opening(x) for x in t])) < 1e-8


def _fall_time(length: float, angle: float) -> float:
    """Time (s) a uniform bar hinged at one end, released horizontal at rest, takes to turn
    to `angle` (rad, negative: downwards): theta'' = 3 g cos(theta) / (2 L) (SciPy)."""
    hit = lambda _t, y: y[0] - angle  # noqa: E731
    hit.terminal = True  # type: ignore[attr-defined]
    ode = solve_ivp(
        lambda _t, y: [y[1], -1.5 * GRAVITY * math.cos(y[0]) / length],
        (0.0, 2.0),
        [0.0, 0.0],
        events=hit,
        rtol=1e-12,
        atol=1e-14,
    )
    return float(ode.t_events[0][0])


def test_each_flap_latches_when_its_free_fall_reaches_the_latch_angle() -> None:
    """The events fire at the compound pendulum's crossing times (within 1e-6 s): the
    flaps' across inertia is m L^2 / 12 about the cm, m L^2 / 3 about the hinge."""
    model = model_by_name("flap_latches")
    solution = _loads(model, 0.5, 1e-9)
    fired = {e.name: e.time for e in solution.events}
    for k, (length, angle) in enumerate(latch.FLAPS):
        assert fired[f"lock{k}"] == pytest.approx(_fall_time(length, angle), abs=1e-6)


def test_the_ball_flies_on_its_parabola_until_it_reaches_the_socket_wall() -> None:
    """Until the first contact the ball flies on x(t) = v0 t + g t^2 / 2 (within 1e-9 m); it
    touches the wall where |x| = clearance (t_c by bisection), and the first output row off
    the parabola is the first after t_c (the rows are 0.1 ms apart)."""
    model = model_by_name("socket_rattle")
    solution = _loads(model, 0.01, 1e-10)
    v0, g = np.array(socket.START_VELOCITY), np.array([0.0, -GRAVITY, 0.0])
    lo, hi = 0.0, 0.01
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        inside = np.linalg.norm(v0 * mid + 0.5 * g * mid**2) < socket.CLEARANCE
        lo, hi = (mid, hi) if inside else (lo, mid)
    t = np.asarray(solution.time)
    path = np.column_stack([solution.channels[f"ball.{c}"] for c in "xyz"])
    flight = v0 * t[:, None] + 0.5 * g * t[:, None] ** 2
    off = np.linalg.norm(path - flight, axis=1) > 1e-9
    assert not np.any(off[t < lo])
    first_off = t[np.argmax(off)]
    assert lo < first_off <= lo + model.output_step + 1e-12
