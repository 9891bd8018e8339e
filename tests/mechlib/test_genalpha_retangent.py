"""When an iteration matrix takes a new differenced tangent
(mechlib.solvers.genalpha.rules.retangents): after a slowly converging step the next matrix
is refactored at its state with the tangent kept, and a new tangent is differenced only when
that refactorisation did not help. On Kane's spin-up beam (benchmarks.flexible, not
stiffened, 8 s at tolerance 1e-6) the rule takes the same steps as the old one (a new
tangent at every slow step: 139 tangents) from one tangent (the first), in 3 % more Newton
iterations (1094 against 1065), and the tip
lag moves by 4e-10 of its range (bound 1e-6, against the run's own error of about 1e-3 of
the range at this tolerance, benchmarks.flexible_compare). Rigid bodies with force elements
keep their tangent first too (rules.keeps_tangent), modal bodies with them do not."""

from __future__ import annotations

import numpy as np

import mechlib
from benchmarks.flexible import SpinUp, spin_up_beam
from mechlib.solvers.genalpha import integrator, rules


def _count_tangents(patch, made: list[int]) -> None:
    """Within `patch`: each differenced tangent the integrator makes counted in made[0]."""
    differenced = integrator.Integrator._differenced_tangent

    def counted(self, *args):
        made[0] += 1
        return differenced(self, *args)

    patch.setattr(integrator.Integrator, "_differenced_tangent", counted)


def _run(monkeypatch, old_rule: bool, old_stall: bool = False, end: float = 8.0):
    made = [0]
    with monkeypatch.context() as patch:
        _count_tangents(patch, made)
        if old_rule:
            patch.setattr(rules, "retangents", lambda tried: True)
        if old_stall:  # every stall on an old matrix took a new tangent
            patch.setattr(rules, "restalled", lambda refreshed, rebuilt, modal: 2 - 2 * refreshed)
        sol = mechlib.solve(
            spin_up_beam(False),
            # each step from Python, where the patched rules are read (the whole runs of
            # mechlib.solvers.genalpha.modal_run have the rules compiled in; the same steps)
            mechlib.Dynamic(end=end, step=0.1, tolerance=1e-6, compiled="steps"),
            requests=[mechlib.PointKinematics("tip", "tip")],
        )
    assert sol.ok, sol.message
    angle = np.array([SpinUp().value(t) for t in sol.time])
    lag = -np.sin(angle) * sol.channels["tip.x"] + np.cos(angle) * sol.channels["tip.y"]
    return sol, lag, made[0]


def test_a_refactorisation_before_a_new_tangent(monkeypatch):
    new, new_lag, new_made = _run(monkeypatch, old_rule=False)
    old, old_lag, old_made = _run(monkeypatch, old_rule=True)
    assert new.stats.steps == old.stats.steps
    assert new.stats.newton_iterations <= 1.05 * old.stats.newton_iterations
    assert new_made < 0.1 * old_made
    assert np.abs(new_lag - old_lag).max() <= 1e-6 * np.ptp(old_lag)


def test_a_stall_refactors_before_a_new_tangent(monkeypatch):
    """rules.restalled: a modal body's stall on a matrix not factored in its step first
    refactors it with the tangent kept. Over the bench's 20 s, measured with the modal
    predictor (kernels.predict_swing): 2275 steps and 7201 iterations from 1 tangent
    (2275 and 7062 from 113 tangents with the old rule), the tip lag 1.4e-6 of its range
    apart. Before that predictor: 2278 steps and
    7998 iterations (2275 and 7989 with the old rule; the same 2275 steps before Newton's
    acceleration test was floored at 10 eps instead of 1e3 eps, rules.ROUNDOFF: which
    steps stall moved) from 1 tangent against 6, the tip lag 1.0e-4 of its range apart
    (bound 3e-4: the runs no longer take the same steps, and differ by about their own
    error at this tolerance, 1e-3 of the range; with the same steps, before, 6e-8). With
    generalized-alpha's step-size rule
    before the pseudo-acceleration was carried (a restart at each change, the step grown
    only by 1.5 or more) it was 2421 steps from 1 tangent against 240: the stalls are
    fewer since."""
    new, new_lag, new_made = _run(monkeypatch, old_rule=False, end=20.0)
    old, old_lag, old_made = _run(monkeypatch, old_rule=False, old_stall=True, end=20.0)
    assert new.stats.steps <= 1.005 * old.stats.steps
    assert new.stats.newton_iterations <= 1.05 * old.stats.newton_iterations
    assert new_made == 1 and new_made < old_made / 3
    assert np.abs(new_lag - old_lag).max() <= 3e-4 * np.ptp(old_lag)
    assert (rules.GIVE_UP, rules.FRESH) == (0, 2)  # the codes the old rule above returns


DISC_INERTIA, DISC_K, DISC_C, DISC_THETA0 = 0.1, 4.0, 0.12, 0.3  # kg*m^2, N*m/rad, N*m*s/rad, rad


def _coiled_disc() -> mechlib.Mechanism:
    """A disc (I = 0.1 kg*m^2 about its axle z) on a torsion spring (4 N*m/rad) and a
    rotational damper (0.12 N*m*s/rad), no gravity: rigid, with force elements."""
    mech = mechlib.Mechanism(name="disc", gravity=(0.0, 0.0, 0.0))
    mech.add_body("disc", mass=10.0, cm=(0, 0, 0), inertia=[0.05, 0.05, DISC_INERTIA])
    mech.add_joint("axle", "revolute", bodies=("disc", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    mech.add_force(mechlib.TorsionSpring("coil", "axle", stiffness=DISC_K))
    mech.add_force(mechlib.RotationalDamper("brake", "axle", damping=DISC_C))
    return mech


def _disc_run(monkeypatch, compiled: str, kept_first: bool = True):
    made = [0]
    with monkeypatch.context() as patch:
        _count_tangents(patch, made)
        if not kept_first:  # the rule before: a new tangent at every slow step
            patch.setattr(rules, "keeps_tangent", lambda modal, elements: False)
        sol = mechlib.solve(
            _coiled_disc(),
            mechlib.Dynamic(end=2.0, step=0.01, tolerance=1e-9, compiled=compiled),
            initial=[mechlib.InitialValue("axle", value=DISC_THETA0)],
            requests=[mechlib.JointCoordinate("a", "axle")],
        )
    assert sol.ok, sol.message
    return sol, made[0]


def _damped_angle(t: np.ndarray) -> np.ndarray:
    """The disc's angle (rad): theta0 e^(-zeta w t) (cos(wd t) + zeta w / wd sin(wd t))."""
    w = np.sqrt(DISC_K / DISC_INERTIA)
    zeta = DISC_C / (2.0 * np.sqrt(DISC_K * DISC_INERTIA))
    wd = w * np.sqrt(1.0 - zeta**2)
    return DISC_THETA0 * np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t))


def test_rigid_bodies_with_elements_keep_their_tangent_first(monkeypatch):
    """rules.keeps_tangent: a rigid system with force elements answers a slow step with a
    refactorisation, its tangent kept, like a modal body without elements. The damped disc
    at tolerance 1e-9 over 2 s, measured: 2223 steps, 6568 Newton iterations and 97
    factorisations from 1 differenced tangent, against 2224 steps, 6629 iterations and 55
    tangents with a new one at each slow step; both within 3.9e-6 rad of the closed form
    (bound 1e-5). The compiled whole runs decide alike: the same steps, iterations and
    factorisations in all three paths."""
    kept, kept_made = _disc_run(monkeypatch, "steps")
    old, old_made = _disc_run(monkeypatch, "steps", kept_first=False)
    assert kept_made <= 2 and old_made >= 20
    assert abs(kept.stats.steps - old.stats.steps) <= 0.005 * old.stats.steps
    assert kept.stats.newton_iterations <= 1.02 * old.stats.newton_iterations
    for sol in (kept, old):
        assert np.abs(sol.channels["a.value"] - _damped_angle(np.asarray(sol.time))).max() < 1e-5
    counts = ("steps", "rejected_steps", "newton_iterations", "factorizations")
    for compiled in ("runs", "python"):
        other, _ = _disc_run(monkeypatch, compiled)
        for name in counts:
            assert getattr(other.stats, name) == getattr(kept.stats, name), (compiled, name)
