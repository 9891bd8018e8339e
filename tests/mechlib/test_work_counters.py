"""Work counters (SolverStats) filled truthfully by every analysis (issue 10 item 1).

Radau's Newton iterations and rejected steps are counted by mechlib from the stage calls
of its right-hand side; the oracle here is SciPy's own collocation solver, spied on: the
iterations it reports (`n_iter`) and the trial step sizes it is called with from each
step start (a new size from the same start is a rejected trial).
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest
import scipy.integrate._ivp.radau as scipy_radau

import mechlib
import mechlib.solvers.radau

from ._models import hinged_bar

SOLVE = importlib.import_module(
    "mechlib.solvers.solve"
)  # the module (mechlib.solve is the function)


def _pendulum(analysis) -> mechlib.Solution:
    return mechlib.solve(
        hinged_bar(),
        analysis,
        initial=[mechlib.InitialValue("hinge", 0.0, 0.0)],
        requests=[mechlib.JointCoordinate("angle", "hinge")],
    )


def test_radau_counts_match_scipy(monkeypatch) -> None:
    """Steps, rejected steps and Newton iterations equal what SciPy's collocation solver
    did (exactly), plus the assembly's and the projections' position iterations; nlu and
    njev are SciPy's. A loose tolerance with a long output interval makes SciPy reject
    some trial steps, so the rejected count is tested non-trivially."""
    collocations, projections, assembly = [], [], []
    solve_collocation = scipy_radau.solve_collocation_system
    solve_positions = mechlib.solvers.radau.solve_positions
    assemble = SOLVE.assemble

    def spy_collocation(fun, t, y, h, *args):
        out = solve_collocation(fun, t, y, h, *args)
        collocations.append((t, h, out[1]))
        return out

    def spy_positions(*args, **kwargs):
        q, its = solve_positions(*args, **kwargs)
        projections.append(its)
        return q, its

    def spy_assemble(*args, **kwargs):
        out = assemble(*args, **kwargs)
        assembly.append(out.newton_iterations)
        return out

    monkeypatch.setattr(scipy_radau, "solve_collocation_system", spy_collocation)
    monkeypatch.setattr(mechlib.solvers.radau, "solve_positions", spy_positions)
    monkeypatch.setattr(SOLVE, "assemble", spy_assemble)
    sol = _pendulum(mechlib.Dynamic(2.0, 0.5, integrator="radau", tolerance=1e-3))
    assert sol.ok
    starts: dict[float, list[float]] = {}
    for t, h, _ in collocations:
        sizes = starts.setdefault(t, [])
        if not sizes or sizes[-1] != h:
            sizes.append(h)
    rejected = sum(len(sizes) - 1 for sizes in starts.values())
    assert rejected > 0
    assert sol.stats.steps == len(starts)
    assert sol.stats.rejected_steps == rejected
    assert sol.stats.newton_iterations == (
        sum(n for *_, n in collocations) + sum(projections) + sum(assembly)
    )


@pytest.mark.parametrize(
    "analysis",
    [
        mechlib.Dynamic(0.5, 0.05),
        mechlib.Dynamic(0.5, 0.05, integrator="radau"),
        mechlib.QuasiStatic(0.5, 0.05),
        mechlib.Static(0.0),
    ],
    ids=["generalized-alpha", "radau", "quasi-static", "static"],
)
def test_every_analysis_fills_every_counter(analysis) -> None:
    """Each analysis reports steps, Newton iterations, factorisations and Jacobian
    evaluations (all > 0 for a pendulum released horizontal), and `as_dict` carries the
    four keys of the summary (SPEC section 3) and the two counters."""
    sol = _pendulum(analysis)
    stats = sol.stats
    assert sol.ok and sol.result is mechlib.Status.SUCCESSFUL
    assert (
        min(stats.steps, stats.newton_iterations, stats.factorizations, stats.jacobian_evaluations)
        > 0
    )
    assert {
        "steps",
        "rejected_steps",
        "newton_iterations",
        "cpu_seconds",
        "factorizations",
        "jacobian_evaluations",
    } == set(stats.as_dict())
    assert np.isfinite(stats.cpu_seconds)


@pytest.mark.parametrize(
    "analysis",
    [mechlib.Dynamic(0.5, 0.05, max_steps=20), mechlib.QuasiStatic(0.5, 0.05, max_steps=3)],
    ids=["generalized-alpha", "quasi-static"],
)
def test_max_steps_is_an_option_with_its_status(analysis) -> None:
    """`max_steps` (accepted and rejected steps) stops the run with status
    MAX_STEPS_REACHED, its message next to the human text, keeping the rows computed."""
    sol = mechlib.solve(
        hinged_bar(),
        analysis,
        throw=False,
        initial=[mechlib.InitialValue("hinge", 0.0, 0.0)],
        requests=[mechlib.JointCoordinate("angle", "hinge")],
    )
    assert not sol.ok and sol.result is mechlib.Status.MAX_STEPS_REACHED
    assert sol.result.code == "max_steps_reached"
    assert "analysis.max_steps" in sol.message and len(sol.time) > 0
    assert sol.stats.steps + sol.stats.rejected_steps == analysis.max_steps
