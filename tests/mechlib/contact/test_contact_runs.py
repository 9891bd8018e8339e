"""Primitive contacts in the compiled whole run (mechlib.solvers.genalpha.run): their memory
(approach speed, last state, static friction anchor) committed in the kernel on each
accepted state by the rule of the Python step (mechlib.elements.contact.memory), the
approach speeds handed back as the history the outputs read, a clearance joint's wear
work carried as an element state.

Against the path it replaces (every step from Python, the compiled Newton loop: StepRun
refused): the bench's steel ball rattling in its socket, with and without Stribeck
friction, dense and steps output, takes the same accepted and rejected steps and Newton
iterations, and every channel the case requests (the contact force, its elastic and
damping parts, which divide by the remembered approach speed, the penetration, the
sliding speed, the wear work, the energy balance) agrees to round-off: measured bit for
bit without friction; with friction the ball spins from its first impact, and the Python
path's differenced tangent holds its quadratic velocity terms while the run's leaves them
out (docs/analyses.md: with the iteration matrices factored in Python the run is bit for
bit again), so the Newton iterates part in the last bits there, positions by
3e-14 (steps) to 1.2e-13 (dense) of their range, the sliding speed (near zero between
impacts) by 6e-12 to 5.9e-10 and the energy balance by 8.8e-12 to 8.0e-10.
"""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from mechlib.elements.contact import Contact, ImpactLaw, SpherePlane
from mechlib.elements.contact import group as contact_group
from mechlib.solvers.genalpha import run as genalpha_run
from tests.mechlib.contact._contact_models import posed_pair

TOL_SAME = 1e-9  # of each channel's range (the compiled Newton loop's test's; measured above)
_REQUESTS = {
    "cf": {"contact": "socket", "quantity": "force"},
    "split": {"contact": "socket", "quantity": "force_split"},
    "pen": {"contact": "socket", "quantity": "penetration"},
    "slide": {"contact": "socket", "quantity": "sliding_speed"},
    "wear": {"contact": "socket", "quantity": "wear_work"},
    "energy": {"quantity": "energy"},
}


def _socket_case(tmp_path, output: str, friction: bool, end=0.012, tolerance=1e-7, max_steps=None):
    """The bench's socket_rattle for `end` s (0.012: its first impacts against the wall)
    at `tolerance` with the contact channels requested; Stribeck friction mu 0.15 / 0.1
    when `friction`; analysis.max_steps when given."""
    from benchmarks.models import model_by_name
    from benchmarks.suite import _case_copy

    case = _case_copy(model_by_name("socket_rattle"), end, tolerance, tmp_path, output)
    data = yaml.safe_load(case.read_text(encoding="utf-8"))
    data["requests"].update(_REQUESTS)
    if max_steps is not None:
        data["analysis"]["max_steps"] = max_steps
    if friction:
        data["mechanism"]["contacts"]["socket"]["friction"] = {
            "mu_static": 0.15,
            "mu_dynamic": 0.1,
        }
    case.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return case


def _solve(case, out, monkeypatch, *, runs: bool):
    """(solution, accepted steps the compiled runs took) of `case`: with the compiled
    runs, or every step from Python (StepRun refused)."""
    from loadcases.run import run_file

    taken = {"steps": 0}
    original = genalpha_run.StepRun.run

    def run(self, s, *args):
        before = self.stepper.stats.steps
        found = original(self, s, *args)
        taken["steps"] += self.stepper.stats.steps - before
        return found

    with monkeypatch.context() as patch:
        patch.setattr(genalpha_run.StepRun, "run", run)
        if not runs:
            patch.setattr(genalpha_run.StepRun, "eligible", staticmethod(lambda stepper: False))
        sol = run_file(case, output_dir=out)[0].solution
    assert sol.ok, sol.message
    return sol, taken["steps"]


@pytest.mark.parametrize("friction", [False, True])
@pytest.mark.parametrize("output", ["dense", "steps"])
def test_socket_runs_as_the_python_steps(tmp_path, monkeypatch, output, friction) -> None:
    """Same steps, rejections and Newton iterations; every requested channel within
    TOL_SAME of its range; the kernel took all but a few steps (the first, and those after
    a failed step, whose new matrix Python factors)."""
    case = _socket_case(tmp_path, output, friction)
    fast, kernel = _solve(case, tmp_path / "runs", monkeypatch, runs=True)
    slow, none = _solve(case, tmp_path / "steps", monkeypatch, runs=False)
    assert none == 0
    counts = ("steps", "rejected_steps", "newton_iterations")
    assert [getattr(fast.stats, c) for c in counts] == [getattr(slow.stats, c) for c in counts]
    assert slow.stats.rejected_steps > 0  # the impacts are in the run
    assert kernel >= 0.9 * fast.stats.steps
    np.testing.assert_array_equal(fast.time, slow.time)
    assert np.ptp(slow.channels["split.damping"]) > 0.0  # the approach speeds are read
    assert np.max(slow.channels["wear.value"]) > 0.0 or not friction
    for name, values in slow.channels.items():
        values = np.asarray(values)
        span = float(np.ptp(values)) if values.size else 0.0
        np.testing.assert_allclose(
            fast.channels[name], values, rtol=0, atol=TOL_SAME * span + 1e-300, err_msg=name
        )


def test_runs_go_on_within_a_step_collapse_window(tmp_path, monkeypatch) -> None:
    """analysis.max_steps 2500 for 0.06 s at tolerance 3e-10: the impacts' steps (about
    1e-7 s) put the pace beyond the limit, so the step-collapse watch opens a window
    (mechlib.solvers.runaway.StepCollapse) and, COLLAPSE_STEPS later, looks at it. Within
    the window the run goes on in the kernel, stopping only where the watch may close it:
    the same counts as the Python steps, which watch the same windows (measured: two
    windows started, two looks), and at least 0.9 of the steps in the kernel (2021 of 2028)."""
    from mechlib.solvers import runaway

    case = _socket_case(tmp_path, "steps", False, end=0.06, tolerance=3e-10, max_steps=2500)
    original = runaway.StepCollapse.watch
    seen: dict[str, int] = {}

    def watch(self, taken, *args):
        if self.since is not None and taken - self.since.taken >= runaway.COLLAPSE_STEPS:
            seen["looked"] = seen.get("looked", 0) + 1
        original(self, taken, *args)
        if self.since is not None and self.since.taken == taken:
            seen["opened"] = seen.get("opened", 0) + 1

    monkeypatch.setattr(runaway.StepCollapse, "watch", watch)
    counts, windows = [], []
    for runs in (True, False):
        seen.clear()
        sol, kernel = _solve(case, tmp_path / str(runs), monkeypatch, runs=runs)
        counts.append((sol.stats.steps, sol.stats.rejected_steps, sol.stats.newton_iterations))
        windows.append(dict(seen))
        if runs:
            assert kernel >= 0.9 * sol.stats.steps
    assert counts[0] == counts[1]
    assert windows[0] == windows[1] and windows[0]["opened"] >= 1 and windows[0]["looked"] >= 1


def test_what_the_runs_carry_of_contacts() -> None:
    """A compiled run carries a primitive contact with its own tangent; not one without
    (a planar system's), nor an impact law whose damping ramp an event moved
    (Contact.start_from while penetrating), whose commit changes the law (Python's)."""
    contact = Contact(
        "c", ("ball", "socket"), SpherePlane((0, 0, 0), 0.01, (0, -0.01, 0), (0, 1, 0)),
        ImpactLaw(1e9, 1.5, damping=1e3, depth=1e-5),
    )  # fmt: skip
    system, q, qd = posed_pair(contact, gravity=9.81, seed=5)
    assert contact_group.runnable([contact])
    contact.own_tangent = False
    assert not contact_group.runnable([contact])
    contact.own_tangent = True
    contact.start_from(system.view(system.kin(q, qd, 0.0)))  # 5e-7 m into the plane
    assert not contact_group.runnable([contact])
    q_apart = q.copy()
    q_apart[1] += 1e-3  # the ball lifted off: the commit moves the ramp back to 0
    contact.commit(system.view(system.kin(q_apart, qd, 1e-3)))
    assert contact_group.runnable([contact])
