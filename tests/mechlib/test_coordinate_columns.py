"""Joint-coordinate requests on whole columns (mechlib.outputs.coordinate_columns) against the
row-by-row evaluation of the measures (each row's snapshot restored, `AngleMeasure.value`,
`.rate`, d(theta)/dq . qdd + quad: what `evaluate_requests` computed row by row before).

Angles, travels and their first rates are bit for bit the row-by-row values (the same
compiled kernels on the stacked rows), angles unwrapped across +-pi with each row's
reference; second rates sum the same products in another order: within 1e-15 of the sum
of the terms' magnitudes (|d(theta)/dq| . |qdd| + |quad|) per row.
"""

from __future__ import annotations

import importlib
import math
from pathlib import Path

import numpy as np

import mechlib as ml
import mechlib.outputs.requests as requests_module
from mechlib.outputs.request_failure import RequestFailure

from ._models import Sine, slider_crank

QUANTITIES = {"A": ("angle", "omega", "alpha"), "D": ("travel", "speed", "accel")}
KINDS = {"angle": "angle", "omega": "angle", "alpha": "angle"}


def _row_by_row(system, trajectory, joint: str, quantity: str) -> tuple[np.ndarray, np.ndarray]:
    """(values, scale of their terms) of a joint coordinate, row by row."""
    m = system.measure(joint, KINDS.get(quantity, "travel"))
    values, scales = [], []
    for i, t in enumerate(trajectory.time):
        system.restore_snapshot(trajectory.references[i])
        k = system.kin(trajectory.q[i], trajectory.qd[i], t)
        if quantity in ("angle", "travel"):
            values.append(m.value(k))
        elif quantity in ("omega", "speed"):
            values.append(m.rate(k))
        else:
            grad, qdd = system.coordinate_gradient(m, k), trajectory.qdd[i]
            values.append(float(grad @ qdd + m.quad(k)))
            scales.append(float(np.abs(grad) @ np.abs(qdd) + abs(m.quad(k))))
    return np.array(values), np.array(scales)


def _captured(monkeypatch, run) -> tuple[list, dict]:
    """The (system, trajectory, requests, channels) of each evaluate_requests call of `run`,
    and how often the row loop ran."""
    calls: list = []
    rows = {"count": 0}
    original, loop = requests_module.evaluate_requests, requests_module._row_by_row

    def spy(system, trajectory, reqs):
        try:
            channels = original(system, trajectory, reqs)
        except RequestFailure as failure:
            calls.append((system, trajectory, reqs, failure.channels))
            raise
        calls.append((system, trajectory, reqs, channels))
        return channels

    def counted(*args):
        rows["count"] += 1
        return loop(*args)

    monkeypatch.setattr(importlib.import_module("mechlib.solvers.solve"), "evaluate_requests", spy)
    monkeypatch.setattr(requests_module, "_row_by_row", counted)
    run()
    return calls, rows


def _check(calls) -> list[str]:
    """Every joint-coordinate column of the captured calls against the row loop."""
    checked = []
    for system, trajectory, reqs, channels in calls:
        for req in reqs:
            if not isinstance(req, ml.JointCoordinate):
                continue
            column = channels[f"{req.name}.value"]
            expected, scale = _row_by_row(system, trajectory, req.joint, req.quantity)
            if req.quantity in ("alpha", "accel"):
                assert np.all(np.abs(column - expected) <= 1e-15 * scale), req.name
            else:
                assert np.array_equal(column, expected), req.name
            checked.append(req.quantity)
    return checked


def _crank() -> ml.Mechanism:
    mech, _ = slider_crank()
    # several revolutions forth and back: the angle crosses +-pi both ways
    mech.add_motion("drive", joint="A", function=Sine(0.3, 4.0 * math.pi, 1.5))
    return mech


def test_crank_angles_travels_and_rates_equal_the_row_loop(monkeypatch) -> None:
    requests: list = [
        ml.JointCoordinate(f"{j}.{q}", j, q) for j, qs in QUANTITIES.items() for q in qs
    ]
    requests.append(ml.JointReaction("RA", "A"))
    calls, rows = _captured(
        monkeypatch, lambda: ml.solve(_crank(), ml.Kinematic(4.0, 0.01), requests=requests)
    )
    assert rows["count"] == 0  # coordinates and reactions only: no row loop
    assert set(_check(calls)) == {q for qs in QUANTITIES.values() for q in qs}
    angle = calls[0][3]["A.angle.value"]
    assert angle.max() > 3.0 * math.pi and angle.min() < -3.0 * math.pi  # unwrapped
    assert np.abs(np.diff(angle)).max() < 1.0


def test_a_failing_expression_keeps_the_coordinate_columns_whole(monkeypatch) -> None:
    """An expression failing from t = 1 s on: its column is NaN from there, the angle's is
    whole and equals the row loop's."""

    def late(t: float, view) -> float:
        if t >= 1.0:
            raise ml.SolverFailure("expression failed", time=t)
        return t

    requests = [ml.JointCoordinate("angle", "A", "angle"), ml.ExpressionOutput("late", late)]
    solutions: list = []
    calls, rows = _captured(
        monkeypatch,
        lambda: solutions.append(
            ml.solve(_crank(), ml.Kinematic(2.0, 0.05), requests=requests, throw=False)
        ),
    )
    sol = solutions[0]
    assert not sol.ok and rows["count"] >= 1
    assert set(_check(calls)) == {"angle"}
    late_column = sol.channels["late.value"]
    assert np.isnan(late_column[sol.time >= 1.0]).all()
    assert np.isfinite(late_column[sol.time < 1.0]).all()
    assert np.isfinite(sol.channels["angle.value"]).all()


def test_fourbar_bench_angles_equal_the_row_loop(monkeypatch, tmp_path: Path) -> None:
    """The four-bar with friction of the bench (`output: steps`, 1e-6): its two joint
    angles, with no row loop run."""
    from benchmarks.models import model_by_name
    from benchmarks.suite import _case_copy
    from loadcases.run import run_file

    model = model_by_name("fourbar_friction")
    case = _case_copy(model, model.end, 1e-6, tmp_path, "steps")
    calls, rows = _captured(monkeypatch, lambda: run_file(case, output_dir=tmp_path / "out"))
    assert rows["count"] == 0
    assert len(_check(calls)) >= 2
