"""Joint reactions and motion efforts of a packed system gathered in batches
(mechlib.kinematics.reactions.gather_in_batches: one compiled call per run of rows with the same
active equations) against the row-by-row gather of the Python path, and against closed
forms.

- A panel swung by a torsion spring (k = 2 N*m/rad, free angle pi) and locked at 90 deg
  by an event: before the lock the hinge carries no moment about its axis, after it the
  lock holds the spring's moment, tz = k (pi/2 - pi) = -pi N*m (1e-6, tolerance 1e-10),
  across the change of active equations.
- The free slider-crank's reactions and the driven crank's motion effort: batched and
  row by row (`packed_constraints` switched off for the requests) equal to 1e-12 of each
  column's peak, or 1e-12 N (N*m) for a column at round-off (the same products).
"""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest

import mechlib as ml
import mechlib.outputs.requests as requests_module
from mechlib.kinematics import reactions

from ._models import G, Ramp, slider_crank

I_HINGE = 0.5  # kg*m^2 about the hinge axis


def _both(monkeypatch, mech, analysis, requests, **kwargs) -> tuple[ml.Solution, ml.Solution]:
    """The run with its loads gathered in batches, then with the row loop; the first must
    have taken the batches."""
    calls = {"batched": 0}
    batched = reactions.gather_in_batches

    def spy(*args):
        calls["batched"] += 1
        return batched(*args)

    monkeypatch.setattr(requests_module, "gather_in_batches", spy)
    fast = ml.solve(mech(), analysis, requests=requests, **kwargs)
    assert calls["batched"] >= 1
    original = requests_module.evaluate_requests

    def row_by_row(system, trajectory, reqs):
        with monkeypatch.context() as patch:
            patch.setattr(system, "packed_constraints", lambda: None)
            return original(system, trajectory, reqs)

    monkeypatch.setattr(
        importlib.import_module("mechlib.solvers.solve"), "evaluate_requests", row_by_row
    )
    slow = ml.solve(mech(), analysis, requests=requests, **kwargs)
    return fast, slow


def _same(fast: ml.Solution, slow: ml.Solution) -> None:
    assert fast.ok and slow.ok
    assert fast.channels.keys() == slow.channels.keys()
    for name, values in slow.channels.items():
        peak = max(np.abs(values).max(), 1.0)  # 1 N or N*m: columns at round-off (tz)
        assert np.abs(fast.channels[name] - values).max() <= 1e-12 * peak, name


def _locked_panel() -> ml.Mechanism:
    mech = ml.Mechanism(gravity=(0.0, 0.0, 0.0))
    mech.add_body("panel", mass=1.0, cm=(0, 0, 0), inertia=[I_HINGE, I_HINGE, I_HINGE])
    mech.add_joint("hinge", "revolute", bodies=("panel", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    mech.add_force(ml.TorsionSpring("drive", "hinge", stiffness=2.0, angle0=math.pi))
    return mech


def test_reactions_across_a_lock(monkeypatch) -> None:
    latch = ml.Event(
        "latch", lambda t, view: view.angle("hinge") - math.pi / 2, (ml.Action("lock", "hinge"),)
    )
    fast, slow = _both(
        monkeypatch,
        _locked_panel,
        ml.Dynamic(end=1.0, step=0.01, tolerance=1e-10),
        [ml.JointReaction("r", "hinge")],
        events=[latch],
    )
    _same(fast, slow)
    t_lock = fast.events[0].time
    before, after = fast.time < t_lock - 1e-9, fast.time > t_lock + 1e-9
    assert before.sum() > 10 and after.sum() > 10
    assert np.abs(fast.channels["r.tz"][before]).max() < 1e-9
    assert fast.channels["r.tz"][after] == pytest.approx(-math.pi, abs=1e-6)


def _free_crank() -> ml.Mechanism:
    mech, _ = slider_crank()
    mech.gravity = (0.0, -G, 0.0)
    return mech


def _driven_crank() -> ml.Mechanism:
    mech = _free_crank()
    mech.add_motion("drive", joint="A", function=Ramp(0.0, 3.0))
    return mech


@pytest.mark.parametrize(
    ("mech", "requests", "initial"),
    [
        (
            _free_crank,
            [ml.JointReaction("A_force", "A"), ml.JointReaction("D_force", "D", frame="slider")],
            [ml.InitialValue("A", 0.0, 2.0 * math.pi)],
        ),
        (
            _driven_crank,
            [ml.JointReaction("A_force", "A"), ml.MotionEffort("drive", "drive")],
            [],
        ),
    ],
    ids=["free-slider-crank", "driven-crank"],
)
def test_batches_equal_the_row_loop(monkeypatch, mech, requests, initial) -> None:
    fast, slow = _both(
        monkeypatch, mech, ml.Dynamic(0.5, 0.005, tolerance=1e-6), requests, initial=initial
    )
    _same(fast, slow)


@pytest.mark.parametrize(
    "rows", [[4, 5, 3, 12, 13], [0, 7], [18, 19, 15], [20], [1, 20, 9], []], ids=str
)
def test_a_selected_pack_fills_its_rows_as_the_whole_pack(rows) -> None:
    """The pack of some of the driven slider-crank's rows (`selected_pack`: joint A's
    spherical and dot-1 rows, a normalisation beside B's spherical row, D's dot-1 and
    dot-2 rows, the motion's coordinate row, mixed, none) fills each of them bit for bit
    as the whole pack does, at a displaced position (a reaction reads its joint's rows)."""
    from mechlib.kinematics import constraint_arrays as ca
    from mechlib.system.planar import make_system

    system = make_system(_driven_crank())
    arrays = system.packed_constraints()
    assert arrays is not None
    nq = 7 * system.nb
    q = system.design_q() + 0.01 * np.sin(np.arange(nq))
    x, _ = ca.state_arrays(q, q, system.nb)

    def filled(ints: np.ndarray, floats: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        full, rows, _, functions, _, _ = ca.row_work(ints, nq)
        active, _ = ca.constraint_rows(x, ints, floats, functions, arrays.references(), full, rows)
        return active, rows

    every_active, every = filled(*arrays.packed())
    chosen = every_active[np.array(rows, dtype=np.int64)]
    active, some = filled(*ca.selected_pack(system, chosen))
    assert len(active) == len(rows)
    for k, row in enumerate(chosen):
        assert np.array_equal(some[active[k]], every[row])
        assert np.any(every[row] != 0.0)
