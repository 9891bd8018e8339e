"""The model check and assembled start a solve keeps for the next solves of the same
mechanism (mechlib.solvers.solve_memo): the next solves find neither again, and their
results are bit for bit those of solves on their own."""

from __future__ import annotations

import dataclasses
import importlib
import math

import numpy as np

import mechlib
from mechlib.solvers.assembly import InitialValue

from ._models import slider_crank


def _counted(monkeypatch) -> dict[str, int]:
    """Calls of the model check and of the assembly from now on."""
    solve_module = importlib.import_module("mechlib.solvers.solve")
    calls = {"check_model": 0, "assemble": 0}
    for name in calls:
        original = getattr(solve_module, name)

        def counting(*args, _original=original, _name=name, **kwargs):
            calls[_name] += 1
            return _original(*args, **kwargs)

        monkeypatch.setattr(solve_module, name, counting)
    return calls


def _same(a: mechlib.Solution, b: mechlib.Solution) -> None:
    """Bit for bit: times, channels, warnings, status, and every counter but the CPU."""
    assert a.status == b.status and a.message == b.message and a.warnings == b.warnings
    assert np.array_equal(a.time, b.time)
    assert a.channels.keys() == b.channels.keys()
    for name in a.channels:
        assert np.array_equal(a.channels[name], b.channels[name]), name
    counters = [f.name for f in dataclasses.fields(a.stats) if f.name != "cpu_seconds"]
    for name in counters:
        assert getattr(a.stats, name) == getattr(b.stats, name), name


def _four_bar() -> mechlib.Mechanism:
    """A planar four-bar built in 3-D with four revolutes (z): redundant equations, which
    `redundant="drop"` drops with a warning each."""
    mech = mechlib.Mechanism(name="four_bar", gravity=(0.0, -9.81, 0.0))
    points = {"A": (0.0, 0.0), "B": (0.0, 0.2), "C": (0.5, 0.35), "D": (0.5, 0.0)}
    for name, (p, q) in {"crank": ("A", "B"), "coupler": ("B", "C"), "rocker": ("C", "D")}.items():
        (x1, y1), (x2, y2) = points[p], points[q]
        mech.add_body(name, mass=1.0, cm=((x1 + x2) / 2, (y1 + y2) / 2, 0.0), inertia=[1e-2] * 3)
    z = (0.0, 0.0, 1.0)
    for joint, bodies, at in (
        ("A", ("crank", "ground"), points["A"]),
        ("B", ("coupler", "crank"), points["B"]),
        ("C", ("rocker", "coupler"), points["C"]),
        ("D", ("rocker", "ground"), points["D"]),
    ):
        mech.add_joint(joint, "revolute", bodies=bodies, at=(*at, 0.0), axis=z)
    return mech


def test_a_companion_reuses_the_check_and_start_with_the_same_results(monkeypatch) -> None:
    """A slider-crank started off its drawing (crank at 0.3 rad, 2 pi rad/s: an assembly of
    Newton iterations) solved, then again with steps twice as long (as an accuracy
    companion): with a memo the second solve checks and assembles nothing, and both are
    bit for bit the solves without one (its counters include the assembly's work)."""
    mech, _ = slider_crank()
    initial = [InitialValue("A", value=0.3, rate=2.0 * math.pi)]
    requests = [
        mechlib.JointReaction("A", "A"),
        mechlib.JointCoordinate("x", "D", "travel"),
    ]
    run = mechlib.Dynamic(end=0.3, step=0.005, tolerance=1e-6)
    companion = dataclasses.replace(run, tolerance=8e-6, step=0.01, max_step=None)
    alone = [mechlib.solve(mech, a, requests=requests, initial=initial) for a in (run, companion)]
    calls = _counted(monkeypatch)
    memo = mechlib.SolveMemo()
    shared = [
        mechlib.solve(mech, a, requests=requests, initial=initial, memo=memo)
        for a in (run, companion)
    ]
    assert calls == {"check_model": 1, "assemble": 1}
    assert alone[0].stats.newton_iterations > alone[0].stats.steps  # the assembly's counted
    for a, b in zip(alone, shared):
        _same(a, b)


def test_dropped_redundant_equations_are_dropped_again(monkeypatch) -> None:
    """A four-bar of four revolutes, `redundant="drop"`: the second solve drops the same
    equations without the check (the same warnings, the same reactions)."""
    mech = _four_bar()
    requests = [mechlib.JointReaction("D", "D")]
    analysis = mechlib.Dynamic(end=0.2, step=0.01)
    kwargs = {"requests": requests, "redundant": "drop"}
    alone = mechlib.solve(mech, analysis, **kwargs)
    assert any(w.startswith("redundant constraint dropped") for w in alone.warnings)
    calls = _counted(monkeypatch)
    memo = mechlib.SolveMemo()
    first, second = (mechlib.solve(mech, analysis, memo=memo, **kwargs) for _ in range(2))
    assert calls == {"check_model": 1, "assemble": 1}
    _same(alone, first)
    _same(alone, second)


def test_a_memo_serves_only_its_own_mechanism_and_initial_values(monkeypatch) -> None:
    """A memo bound to one solve's mechanism and initial values is not read by a solve of
    another mechanism or other initial values (each checks and assembles anew), and
    those solves are the ones without a memo."""
    mech, _ = slider_crank()
    other, _ = slider_crank(0.12, 0.3)
    analysis = mechlib.Dynamic(end=0.1, step=0.01)
    spin = [InitialValue("A", rate=1.0)]
    faster = [InitialValue("A", rate=3.0)]
    calls = _counted(monkeypatch)
    memo = mechlib.SolveMemo()
    mechlib.solve(mech, analysis, initial=spin, memo=memo)
    solved = mechlib.solve(other, analysis, initial=spin, memo=memo)
    again = mechlib.solve(mech, analysis, initial=faster, memo=memo)
    assert calls == {"check_model": 3, "assemble": 3}
    _same(solved, mechlib.solve(other, analysis, initial=spin))
    _same(again, mechlib.solve(mech, analysis, initial=faster))


def _counted_patterns(monkeypatch) -> list[int]:
    """One entry per saddle pattern found from now on (not taken from a memo)."""
    module = importlib.import_module("mechlib.system.known_patterns")
    found: list[int] = []
    original = module.generic_pattern

    def counting(system):
        found.append(1)
        return original(system)

    monkeypatch.setattr(module, "generic_pattern", counting)
    return found


def test_a_companion_shares_the_run_s_saddle_pattern(monkeypatch) -> None:
    """The run finds the saddle pattern of its rows, its companion (the same memo) takes
    it, where without a memo each solve finds its own; the solves are bit for bit the
    same (the pattern is the mechanism's and its active rows' alone: the one kept has the
    nonzeros a system finds anew)."""
    from mechlib.system.known_patterns import KnownPatterns, generic_pattern
    from mechlib.system.planar import make_system

    mech, _ = slider_crank()
    initial = [InitialValue("A", value=0.3, rate=2.0 * math.pi)]
    run = mechlib.Dynamic(end=0.1, step=0.005, tolerance=1e-6)
    companion = dataclasses.replace(run, step=0.01)
    alone = [mechlib.solve(mech, a, initial=initial) for a in (run, companion)]
    found = _counted_patterns(monkeypatch)
    [mechlib.solve(mech, a, initial=initial) for a in (run, companion)]
    assert len(found) == 2
    found.clear()
    memo = mechlib.SolveMemo()
    shared = [mechlib.solve(mech, a, initial=initial, memo=memo) for a in (run, companion)]
    assert len(found) == 1
    for a, b in zip(alone, shared):
        _same(a, b)
    (kept,) = memo.patterns.found.values()
    fresh = generic_pattern(make_system(mech))
    for name in ("rows", "cols", "indptr", "indices"):
        assert np.array_equal(getattr(kept, name), getattr(fresh, name)), name
    # a system that made a lock finds its own and keeps none (a lock's row is numbered in
    # the order of events: the same rows may be another joint's lock in another solve)
    system = make_system(mech)
    KnownPatterns().attach(system)
    store = system.known_patterns[0]
    first = system.saddle_pattern()
    other = make_system(mech)
    store.attach(other)
    assert other.saddle_pattern() is first
    locked = make_system(mech)
    store.attach(locked)
    locked.lock("A", locked.kin(locked.design_q()))
    found.clear()
    assert locked.saddle_pattern() is not first and len(found) == 1
    assert list(store.found.values()) == [first]
