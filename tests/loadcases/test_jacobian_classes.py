"""The static stiffness's constraint Jacobians shared by bodies that no equation joins
(mechlib.system.fd_columns.JacobianClasses, mechlib.solvers.static.balance): the classes of a chain
and of the door, and the differenced stiffness equal, entry for entry, to the one that evaluates the
whole constraint Jacobian in every column.

Door (loadcases/library/door/lifting_inner.case.yaml): 15 bodies, 104 equations; the door
is joined to ten bodies, which share no equation among themselves, so 3 classes: 21
Jacobian evaluations per stiffness instead of 105. The multipliers are random (the
stiffness is a derivative anywhere), the pose a random disturbance of the assembled one.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import mechlib.solvers.static.balance
from loadcases.build.model import build_run
from loadcases.inputs.loader import load_case
from mechlib.solvers.assembly import solve_positions
from mechlib.solvers.static.balance import Balance
from mechlib.system.fd_columns import JacobianClasses
from mechlib.system.system import System
from tests.mechlib.test_fd_columns import _chain, _state

DOOR = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "door"


def _whole(system: System, t: float, q: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """The stiffness with the whole Jacobian evaluated in every column."""
    balance = Balance(system, t, q)
    balance._classes = None
    return balance.stiffness(q, lam)


@pytest.fixture(scope="module")
def door() -> System:
    return System(build_run(load_case(DOOR / "lifting_inner.case.yaml")).mechanism)


def test_chain_classes_and_stiffness():
    system = System(_chain())
    a, b, c = (system.body_index(n) for n in "abc")
    classes = JacobianClasses.of(system)
    assert classes is not None
    assert sorted(classes.classes) == sorted([(b,), (a, c)])  # j2 joins a-b, j3 b-c
    m = len(system.labels)
    rows_of = {n: set(classes.rows[n].tolist()) for n in (a, b, c)}
    assert rows_of[a] | rows_of[b] | rows_of[c] == set(range(m))
    assert not rows_of[a] & rows_of[c]  # no equation joins a and c
    q, _, lam = _state(system)
    fast = Balance(system, 0.3, q).stiffness(q, lam)
    np.testing.assert_array_equal(fast, _whole(system, 0.3, q, lam))
    assert np.abs(fast).max() > 1.0


def test_door_classes(door):
    classes = JacobianClasses.of(door)
    assert classes is not None
    assert len(classes.classes) == 3
    assert sorted(b for c in classes.classes for b in c) == list(range(door.nb))
    pattern = door.phi_q(door.kin(door.design_q())) != 0.0
    for bodies in classes.classes:  # no equation touches two bodies of one class
        for one in bodies:
            for other in bodies:
                if one < other:
                    assert not set(classes.rows[one]) & set(classes.rows[other])
    for body, rows in classes.rows.items():  # every equation reading the body is listed
        reading = np.flatnonzero(pattern[:, 7 * body : 7 * body + 7].any(axis=1))
        assert set(reading) <= set(rows.tolist())


def test_door_stiffness_equals_whole_jacobian_per_column(door):
    rng = np.random.default_rng(11)
    q, _ = solve_positions(door, door.design_q(), 0.0)
    q = q + 1e-4 * rng.standard_normal(door.nq)
    lam = 1e3 * rng.standard_normal(door.phi(door.kin(q)).size)
    fast = Balance(door, 0.0, q).stiffness(q, lam)
    whole = _whole(door, 0.0, q, lam)
    np.testing.assert_array_equal(fast, whole)
    assert np.abs(whole).max() > 1e5  # the contacts' and joints' stiffness is there


def test_a_wrong_class_is_seen(door, monkeypatch):
    """Bodies joined by an equation put in one class: the columns of the first change."""
    classes = JacobianClasses.of(door)
    assert classes is not None
    wrong = JacobianClasses([tuple(range(door.nb))], classes.rows)
    monkeypatch.setattr(mechlib.solvers.static.balance, "_jacobian_classes", lambda system: wrong)
    rng = np.random.default_rng(11)
    q, _ = solve_positions(door, door.design_q(), 0.0)
    lam = 1e3 * rng.standard_normal(door.phi(door.kin(q)).size)
    bad = Balance(door, 0.0, q).stiffness(q, lam)
    whole = _whole(door, 0.0, q, lam)
    assert np.abs(bad - whole).max() > 1e-5 * np.abs(whole).max()  # measured: 4e-4


def _rates_by_least_squares(system: System, q: np.ndarray, t: float):
    k = system.kin(q, None, t)
    jac = system.phi_q(k)
    qd = np.linalg.lstsq(jac, system.nu(k), rcond=None)[0]
    return qd, np.linalg.lstsq(jac, system.gamma(system.kin(q, qd, t)), rcond=None)[0]


def test_rates_from_one_factorization_equal_least_squares(door, monkeypatch):
    """solve_rates (one QR of phi_q for qd and qdd) against two SVD least squares, on the
    lifting door at its assembled pose with its motions' rates at t = 0.5 s (opening): equal to
    round-off (measured 3e-14 and 5e-14 of the largest rate for lifting_inner: its phi_q is
    well conditioned); with the rank test failing, exactly the least-squares numbers."""
    import mechlib.solvers.assembly
    from mechlib.solvers.assembly import solve_rates

    q, _ = solve_positions(door, door.design_q(), 0.5)
    qd, qdd = solve_rates(door, q, 0.5)
    ref_qd, ref_qdd = _rates_by_least_squares(door, q, 0.5)
    assert np.abs(ref_qd).max() > 0.1 and np.abs(ref_qdd).max() > 0.01  # it moves
    np.testing.assert_allclose(qd, ref_qd, rtol=0, atol=1e-13 * np.abs(ref_qd).max())
    np.testing.assert_allclose(qdd, ref_qdd, rtol=0, atol=1e-12 * np.abs(ref_qdd).max())
    monkeypatch.setattr(mechlib.solvers.assembly, "_RANK_RATIO", 1.0)  # every pivot "too small"
    fallback = solve_rates(door, q, 0.5)
    np.testing.assert_array_equal(fallback[0], ref_qd)
    np.testing.assert_array_equal(fallback[1], ref_qdd)
