"""The compiled generalized-alpha Newton loop and constraint kernels
(mechlib.solvers.genalpha.compiled,
mechlib.kinematics.constraint_arrays) against the Python code they replace, and the motion they give
against closed forms.

- The packed constraint kernels give the grouped path's residuals and rows
  (System.grouped_phi_and_jacobian), and the right sides nu and gamma, to 1e-12 at generic
  states (every primitive group, angles past +-pi, travels, a screw, a gear and a motion;
  after a lock and a dropped row); the system uses them once compiled.
- The LU solve from dense getrf factors and from SuperLU's L and U equals
  mechlib.linalg.factor.solve_factored to 1e-12 (band factors: tests/mechlib/test_flat_lu.py).
- Whole runs through the compiled loop and through the Python loop (`arrays = None`) take
  the same steps and Newton iterations and give every output to 1e-9 of its peak (measured
  1e-13 to 1e-10): the free slider-crank (dense factors), a 12-link chain (band factors),
  a driven crank (a motion: the coordinate rows and their time functions).
- The pendulum through the compiled loop meets the elliptic-integral period (1e-6) and the
  energy is conserved to 1e-6 of m g L over 3 s (generalized-alpha at tolerance 1e-8).
- The toggle check's compiled rows give the Python rows' measures to 1e-12.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechlib
from mechlib.kinematics.constraint_arrays import ConstraintArrays, nu_and_gamma, phi_and_jacobian
from mechlib.linalg.factor import factor, factor_saddle, solve_factored
from mechlib.linalg.flat_lu import factor_data, lu_solve
from mechlib.solvers.genalpha.integrator import Integrator
from mechlib.system.system import System

from ._models import (
    PENDULUM_REQUESTS,
    Bar,
    falling_chain,
    falling_slider_crank,
    hinged_bar,
    pendulum_errors,
    slider_crank,
)
from .test_coordinate_block import _mechanism as _coordinate_mechanism

TOL = 1e-12
TOL_PERIOD = 3e-6  # measured 1.5e-6 (the phase error of generalized-alpha at 1e-8)
TOL_ENERGY = 2e-5  # measured 9.3e-6 (numerical damping, rho_inf < 1)


def _kernel_rows(system: System, k) -> tuple[np.ndarray, ...]:
    """(phi, phi_q, nu, gamma) of `system` at state k from the packed kernels."""
    arrays = ConstraintArrays(system)
    ints, floats = arrays.packed()
    functions, refs = arrays.functions(k.t), arrays.references()
    m = system.active.size
    phi, jac, nu, gamma = np.empty(m), np.empty((m, system.nq)), np.empty(m), np.empty(m)
    phi_and_jacobian(k.x, ints, floats, functions, refs, phi, jac)
    nu_and_gamma(k.x, k.xd, ints, floats, functions, refs, nu, gamma)
    return phi, jac, nu, gamma


def _kernel_mechanism() -> mechlib.Mechanism:
    """The coordinate-block test's mechanism without its point on a curve (which keeps
    the grouped path), with a slider-crank added: spherical, dot-1 and dot-2 rows."""
    mech = _coordinate_mechanism()
    del mech.joints["C"]
    crank, _ = slider_crank()
    for name, body in crank.bodies.items():
        mech.add_body(name, mass=body.mass, cm=body.cm, inertia=body.inertia)
    for joint in crank.joints.values():
        mech.joints[joint.name] = joint
    return mech


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_kernels_match_the_system(seed: int) -> None:
    system = System(_kernel_mechanism())
    assert ConstraintArrays.eligible(system)
    rng = np.random.default_rng(seed)
    q = system.design_q() + 0.3 * rng.standard_normal(system.nq)
    k = system.kin(q, rng.standard_normal(system.nq), 0.7)
    for m in system.angle_measures:  # unwrap against references a turn or more away
        m.reference = float(rng.choice([-7.0, 0.0, 7.0]))
    phi, jac = system.grouped_phi_and_jacobian(k)
    expected = (phi, jac, system.nu(k), system.gamma(k))
    for got, want in zip(_kernel_rows(system, k), expected):
        assert got.shape == want.shape
        assert np.abs(got - want).max() < TOL * max(1.0, np.abs(want).max())


def test_kernels_follow_a_lock_and_a_dropped_row() -> None:
    system = System(_kernel_mechanism())
    k = system.kin(system.design_q(), np.zeros(system.nq), 0.0)
    system.lock("R2", k)
    system.drop_rows([3])
    q = system.design_q() + 0.1
    k = system.kin(q, np.ones(system.nq), 0.2)
    phi, jac = system.grouped_phi_and_jacobian(k)
    for got, want in zip(_kernel_rows(system, k), (phi, jac, system.nu(k), system.gamma(k))):
        assert got.shape == want.shape
        assert np.abs(got - want).max() < TOL * max(1.0, np.abs(want).max())


def test_curve_joints_keep_the_grouped_path() -> None:
    assert not ConstraintArrays.eligible(System(_coordinate_mechanism()))


def test_the_system_evaluates_its_rows_in_one_call() -> None:
    """Once the kernels are compiled, System.phi_and_jacobian and phi_q are the packed
    kernels' (equal to the grouped path to 1e-12)."""
    system = System(_kernel_mechanism())
    k = system.kin(system.design_q() + 0.05, np.ones(system.nq), 0.3)
    system.grouped_phi_and_jacobian(k)  # compiles the kernels if no test did
    assert system.packed_constraints() is not None
    phi, jac = system.phi_and_jacobian(k)
    want_phi, want_jac = system.grouped_phi_and_jacobian(k)
    assert np.abs(phi - want_phi).max() < TOL and np.abs(jac - want_jac).max() < TOL
    assert np.abs(system.phi_q(k) - want_jac).max() < TOL
    assert np.abs(system.phi(k) - want_phi).max() < TOL
    groups = np.concatenate([g.gamma(k) for g in system.groups])
    block = system.coordinate_rows().gamma(k)
    want_gamma = np.concatenate([groups, block])[system.active]
    assert np.abs(system.gamma(k) - want_gamma).max() < TOL * np.abs(want_gamma).max()


@pytest.mark.parametrize("n", [30, 160])  # dense LAPACK below 100 rows; SuperLU (no band)
def test_lu_solve_matches_solve_factored(n: int) -> None:
    rng = np.random.default_rng(n)
    top = rng.standard_normal((n, n))
    top = top @ top.T + n * np.eye(n)
    jac = rng.standard_normal((n // 3, n)) * (rng.random((n // 3, n)) < 0.1)
    jac[np.arange(n // 3), np.arange(n // 3)] += 1.0
    if n >= 100:
        from mechlib.linalg.factor import SaddlePattern

        lu = factor_saddle(top, jac, SaddlePattern(top, jac))
        assert not isinstance(lu, tuple)  # the sparse factors
    else:
        lu = factor(np.block([[top, jac.T], [jac, np.zeros((n // 3, n // 3))]]))
    b = rng.standard_normal(n + n // 3)
    want = solve_factored(lu, b)
    got = lu_solve(*factor_data(lu), b)
    assert np.abs(got - want).max() < TOL * np.abs(want).max()


def test_saddle_matrix_gathered_on_its_pattern() -> None:
    """The sparse saddle matrix gathered from the mass matrix and the Jacobian on the
    pattern equals the dense [[M, J^T], [J, 0]] exactly (a 12-link chain at a generic
    state)."""
    from mechlib.linalg.factor import SaddlePattern, augmented

    mech, _, _ = _chain()
    system = System(mech)
    rng = np.random.default_rng(3)
    k = system.kin(system.design_q() + 0.1 * rng.standard_normal(system.nq), None, 0.0)
    top, jac = system.mass(k), system.phi_q(k)
    pattern = SaddlePattern(top, jac)
    assert np.array_equal(pattern.csc(pattern.values(top, jac)).toarray(), augmented(top, jac))


def test_saddle_factors_gathered_by_the_kernel() -> None:
    """The saddle matrix's factors from the kernel's values on the pattern
    (mechlib.system.saddle) solve as those of the dense M and phi_q, to 1e-12 (a 12-link chain:
    132 rows, the band path)."""
    from mechlib.linalg.factor import factor_saddle
    from mechlib.system.saddle import rigid_saddle_factors

    mech, _, _ = _chain()
    system = System(mech)
    rng = np.random.default_rng(4)
    k = system.kin(system.design_q() + 0.1 * rng.standard_normal(system.nq), None, 0.0)
    system.phi_q(k)  # compiles the kernels if no test did
    assert system.packed_constraints() is not None
    n = system.nq + system.active.size
    assert n >= 100
    b = rng.standard_normal(n)
    want = solve_factored(
        factor_saddle(system.mass(k), system.phi_q(k), system.saddle_pattern()), b
    )
    got = solve_factored(rigid_saddle_factors(system, k), b)
    assert np.abs(got - want).max() < TOL * np.abs(want).max()


def _free_crank() -> tuple[mechlib.Mechanism, list, list]:
    mech = falling_slider_crank()
    initial = [mechlib.InitialValue("A", 0.0, 2.0 * math.pi)]
    requests = [
        mechlib.JointReaction("A_force", "A"),
        mechlib.JointCoordinate("A_angle", "A"),
        mechlib.JointReaction("D_force", "D"),
    ]
    return mech, initial, requests


def _chain(links: int = 12) -> tuple[mechlib.Mechanism, list, list]:
    mech = falling_chain(links)
    return mech, [], [mechlib.PointKinematics("tip", "tip"), mechlib.JointReaction("s0", "s0")]


def _driven_crank() -> tuple[mechlib.Mechanism, list, list]:
    requests = [mechlib.JointReaction("A_force", "A"), mechlib.MotionEffort("drive", "drive")]
    return falling_slider_crank(drive=3.0), [], requests


def _both_paths(model, analysis) -> tuple[mechlib.Solution, mechlib.Solution]:
    """The run through the compiled loop, then through the Python loop."""
    runs = []
    original = Integrator.__init__

    for compiled in (True, False):

        def init(self, *args, _compiled=compiled, **kwargs):
            original(self, *args, **kwargs)
            if not _compiled:
                self.arrays = None

        Integrator.__init__ = init  # type: ignore[method-assign]
        try:
            mech, initial, requests = model()
            runs.append(mechlib.solve(mech, analysis, initial=initial, requests=requests))
        finally:
            Integrator.__init__ = original  # type: ignore[method-assign]
    return runs[0], runs[1]


@pytest.mark.parametrize(
    ("model", "analysis"),
    [
        (_free_crank, mechlib.Dynamic(0.5, 0.001, tolerance=1e-6)),
        (_chain, mechlib.Dynamic(0.3, 0.01, tolerance=1e-6)),
        (_driven_crank, mechlib.Dynamic(0.5, 0.01, tolerance=1e-6)),
    ],
    ids=["free-slider-crank", "chain-band", "driven-crank"],
)
def test_compiled_loop_equals_the_python_loop(model, analysis) -> None:
    compiled, python = _both_paths(model, analysis)
    assert compiled.ok and python.ok
    assert compiled.stats.steps == python.stats.steps > 10
    assert compiled.stats.newton_iterations == python.stats.newton_iterations
    assert compiled.stats.rejected_steps == python.stats.rejected_steps
    for name, values in python.channels.items():
        peak = np.abs(values).max()
        if peak > 1e-9:  # components at round-off (out-of-plane ones) have no scale
            assert np.abs(compiled.channels[name] - values).max() < 1e-9 * peak, name


def test_pendulum_through_the_compiled_loop_meets_the_closed_form() -> None:
    """A bar released from the horizontal swings through 180 deg and back with the period
    T = 4 sqrt(I_O / (m g L/2)) K(sin^2(pi/4)) (elliptic integral, amplitude 90 deg about
    the hanging position): the last return to the horizontal (the vertex of the parabola
    through the three rows around the angle's maximum) lands on a multiple of T within
    TOL_PERIOD, and m g (L/2) sin(theta) + I_O omega^2 / 2 stays within TOL_ENERGY of
    m g L (generalized-alpha at tolerance 1e-8, through the compiled loop)."""
    bar = Bar()
    system = System(hinged_bar(bar))
    assert ConstraintArrays.eligible(system) and not system.elements
    sol = mechlib.solve(
        hinged_bar(bar),
        mechlib.Dynamic(3.0, 0.001, tolerance=1e-8),
        requests=list(PENDULUM_REQUESTS),
    )
    assert sol.ok
    period, energy = pendulum_errors(sol, bar)
    assert period < TOL_PERIOD and energy < TOL_ENERGY


def test_toggle_rows_from_the_kernels_equal_the_python_rows(monkeypatch) -> None:
    """The free slider-crank passes its dead points: the toggle check's rank measures per
    recorded row from the compiled rows equal those of the per-row Python path to 1e-12,
    and so do the warnings: none, since the slider merely reverses there (the Jacobian
    keeps its rank, its smallest singular value stays above 0.8 of its largest)."""
    import importlib

    import mechlib.checks.singularity as singularity

    captured: list = []

    def both(system, trajectory, *args):
        assert system.packed_constraints() is not None
        compiled = (
            singularity._series(system, trajectory),
            singularity.toggle_warnings(system, trajectory, *args),
        )
        with monkeypatch.context() as patch:  # the per-row Python path
            patch.setattr(system, "packed_constraints", lambda: None)
            python = (
                singularity._series(system, trajectory),
                singularity.toggle_warnings(system, trajectory, *args),
            )
        captured.append((compiled, python))
        return compiled[1]

    monkeypatch.setattr(importlib.import_module("mechlib.solvers.solve"), "toggle_warnings", both)
    mech, initial, requests = _free_crank()
    sol = mechlib.solve(mech, mechlib.Dynamic(1.0, 0.002), initial=initial, requests=requests)
    assert sol.ok and captured
    (ranks, warnings), (ranks_py, warnings_py) = captured[0]
    assert len(ranks) == len(sol.time)
    angle = sol.channels["A_angle.value"]
    assert angle.max() - angle.min() > 2.0 * math.pi  # a full turn: both dead points passed
    assert ranks.min() > 0.8 * ranks.max()
    assert np.abs(ranks - ranks_py).max() < TOL
    assert warnings == warnings_py == sol.warnings == []


def test_angles_commit_in_one_call() -> None:
    """System.commit unwraps every joint angle against its reference in one kernel call:
    the same references as each AngleMeasure.commit (to 1e-12 rad), a turn or more away."""
    system = System(_kernel_mechanism())
    rng = np.random.default_rng(5)
    k = system.kin(system.design_q() + 0.3 * rng.standard_normal(system.nq), None, 0.0)
    start = {id(m): float(rng.choice([-7.0, 0.0, 7.0])) for m in system.angle_measures}
    for m in system.angle_measures:
        m.reference = start[id(m)]
        m.commit(k)
    want = [m.reference for m in system.angle_measures]
    for m in system.angle_measures:
        m.reference = start[id(m)]
    arrays = ConstraintArrays(system)
    arrays.commit_angles(k)
    got = [m.reference for m in system.angle_measures]
    assert len(got) >= 3 and max(abs(a) for a in got) > math.pi
    assert np.abs(np.array(got) - np.array(want)).max() < TOL
