"""The compiled projection of dense output rows (mechlib.solvers.dense_compiled) against the Python
projection it replaces (mechlib.solvers.assembly.solve_positions + mechlib.solvers.consistent.
consistent_state), and the motion it gives against closed forms.

- Whole dense runs with the compiled rows and with the Python rows (`_compiled_row`
  switched off) take the same steps, Newton iterations, factorisations and Jacobian
  evaluations, and give every output to 1e-9 of its peak (measured 3.5e-10 and 2.3e-10: the
  compiled row takes the Jacobian of Newton's iterate before its last step, within the
  position tolerance 1e-10 of q; 1.8e-11 and 4.5e-14 when it was evaluated at q once
  more): the free slider-crank through its dead points, a driven crank (a motion: the
  coordinate rows and their time functions); every row of both took the compiled path.
- The rows of the free slider-crank meet the equations of motion they claim: phi = 0 to
  1e-10, phi_q qd = nu and phi_q qdd = gamma to 1e-9, M qdd + phi_q^T lam = Q to 1e-9 of
  the largest load (residuals computed by the Python System, not the kernel).
- The pendulum released from the horizontal with dense rows: its energy stays within
  2e-5 of m g L (measured 1.3e-5) and its period meets the elliptic integral to 4e-6
  (measured 2.6e-6).
- The kernel's interpolant is the quintic Hermite of both ends (exact for a quintic).
- Its M^-1 in closed form times M is the identity to 1e-12 (|p| = 1 or not); its Cholesky
  factor (loops) is LAPACK's; its nu alone is `nu_and_gamma`'s.
- The rows' products over the Jacobian blocks each row touches (`row_work`) are the full
  products bit for bit: the entries left out are zeros at any state.
- Where the kernel cannot vouch for its solve (a singular or non-finite matrix, Newton
  not converging) it gives up and the Python path takes the row.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np
import pytest

import mechlib
import mechlib.solvers.dense as dense
from mechlib.core import jit
from mechlib.elements.compiled_forces import no_forces
from mechlib.kinematics import constraint_arrays as ca
from mechlib.kinematics import kernels as kr
from mechlib.kinematics.constraint_arrays import ConstraintArrays
from mechlib.solvers.dense_compiled import (
    DONE,
    FALLBACK,
    _cholesky,
    _factored,
    _inverse_mass,
    _lower_product,
    _times,
    _transpose_times,
    _well_conditioned,
    interpolated,
    inverse_inertia,
    project_loaded_row,
    project_loaded_rows,
    project_row,
    row_work,
)
from mechlib.system.system import System

from ._models import PENDULUM_REQUESTS, Bar, falling_slider_crank, hinged_bar, pendulum_errors

# of each output's peak: the compiled rows' Jacobian is taken up to dense.ONE_STEP (1e-9) of
# their q (one exact Newton step), the Python rows' within the position tolerance (1e-10);
# measured 1.5e-9 (free) and 2.4e-9 (driven), 3.5e-10 and 2.3e-10 with the full Newton
TOL_SAME = 5e-9
TOL_PERIOD = 4e-6  # measured 2.6e-6 (generalized-alpha's phase error at 1e-8)
TOL_ENERGY = 2e-5  # measured 1.3e-5 (generalized-alpha's numerical damping)


def _packed_system() -> tuple[System, ConstraintArrays]:
    """The free slider-crank's System and its packed constraints (kernels compiled)."""
    jit.compile_all()
    mech, _, _ = _free_crank()
    system = System(mech)
    arrays = system.packed_constraints()
    assert arrays is not None
    return system, arrays


def _ends(q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """A step's ends (6, nq) whose row at s = 1 is (q, qd) as given."""
    ends = np.zeros((6, q.size))
    ends[3], ends[4] = q, qd
    return ends


def _free_crank() -> tuple[mechlib.Mechanism, list, list]:
    mech = falling_slider_crank()
    initial = [mechlib.InitialValue("A", 0.0, 2.0 * math.pi)]
    requests = [mechlib.JointReaction("A_force", "A"), mechlib.JointReaction("D_force", "D")]
    return mech, initial, requests


def _driven_crank() -> tuple[mechlib.Mechanism, list, list]:
    requests = [mechlib.JointReaction("A_force", "A"), mechlib.MotionEffort("drive", "drive")]
    return falling_slider_crank(drive=3.0), [], requests


def _crank_packed() -> tuple[System, Any, tuple[np.ndarray, np.ndarray]]:
    """The driven crank's system, its packed constraints and their (ints, floats)."""
    system = System(_driven_crank()[0])
    arrays = system.packed_constraints()
    assert arrays is not None
    return system, arrays, arrays.packed()


def _run(model, analysis, monkeypatch, *, compiled: bool) -> tuple[mechlib.Solution, dict]:
    """The dense run of `model`, step by step (`Dynamic.compiled = "steps"`: no compiled
    runs of steps, which project their rows in the same kernel), its rows from the kernel
    (a step's rows in one call, or one by one) or (compiled False: `"python"`) from
    Python; also how many rows asked the kernel and how many it took."""
    taken = {"asked": 0, "done": 0}
    original, original_block = dense._compiled_row, dense.HermiteRows.block

    def row(*args):
        taken["asked"] += 1
        got = original(*args)
        taken["done"] += got is not None
        return got

    def block(self, start, end, times, z0, z1):  # a step's rows in one call
        got = original_block(self, start, end, times, z0, z1)
        taken["asked"] += len(times) if got is not None else 0
        taken["done"] += got.rows if got is not None else 0
        return got

    analysis = dataclasses.replace(analysis, compiled="steps" if compiled else "python")
    with monkeypatch.context() as patch:
        patch.setattr(dense, "_compiled_row", row)  # counts; the path is the analysis's
        patch.setattr(dense.HermiteRows, "block", block)
        mech, initial, requests = model()
        return mechlib.solve(mech, analysis, initial=initial, requests=requests), taken


@pytest.mark.parametrize(
    "model", [_free_crank, _driven_crank], ids=["free-slider-crank", "driven-crank"]
)
def test_compiled_rows_equal_the_python_rows(model, monkeypatch) -> None:
    analysis = mechlib.Dynamic(1.0, 0.002, tolerance=1e-6, dense=True)
    fast, fast_rows = _run(model, analysis, monkeypatch, compiled=True)
    slow, slow_rows = _run(model, analysis, monkeypatch, compiled=False)
    assert fast.ok and slow.ok
    assert fast_rows["done"] == fast_rows["asked"] >= len(fast.time) - 1
    assert slow_rows["asked"] == 0
    counts = ("steps", "newton_iterations", "factorizations", "jacobian_evaluations")
    for name in counts:
        assert getattr(fast.stats, name) == getattr(slow.stats, name), name
    assert fast.warnings == slow.warnings
    for name, values in slow.channels.items():
        peak = np.abs(values).max()
        if peak > 1e-9:  # components at round-off (out-of-plane ones) have no scale
            assert np.abs(fast.channels[name] - values).max() < TOL_SAME * peak, name


def test_compiled_rows_meet_the_equations_of_motion() -> None:
    """Each projected row, checked with the Python System's own residuals."""
    system, arrays = _packed_system()
    rng = np.random.default_rng(3)
    nq, m = system.nq, system.active.size
    design = system.design_q()
    for t in (0.0, 0.3, 0.7):
        q = design + 1e-4 * rng.standard_normal(nq)  # off the constraints, as interpolated
        qd = rng.standard_normal(nq)
        out = np.empty(3 * nq + m)
        ints, floats = arrays.packed()
        status, fresh = project_row(
            _ends(q, qd), 1.0, 1.0, ints, floats, arrays.functions(t), arrays.references(),
            arrays.bodies(), dense.PROJECTION, out,
        )  # fmt: skip
        assert status == DONE and fresh >= 1
        q1, qd1, qdd1, lam1 = out[:nq], out[nq : 2 * nq], out[2 * nq : 3 * nq], out[3 * nq :]
        k = system.kin(q1, qd1, t)
        jac = system.phi_q(k)
        assert np.abs(system.phi(k)).max() < 1e-10
        assert np.abs(jac @ qd1 - system.nu(k)).max() < 1e-9 * np.abs(qd1).max()
        assert np.abs(jac @ qdd1 - system.gamma(k)).max() < 1e-9 * np.abs(qdd1).max()
        loads = system.forces(k)
        balance = system.mass_times(k, qdd1) + jac.T @ lam1 - loads
        assert np.abs(balance).max() < 1e-9 * max(np.abs(loads).max(), np.abs(jac.T @ lam1).max())


def test_one_exact_newton_step_is_taken_as_converged() -> None:
    """A row whose q lies 3e-10 off the constraints (an interpolant's, as the integrator's
    steps leave them: 1e-10 to 1e-6) stops after its first, exact, Newton step (below
    dense.ONE_STEP; the full Newton takes a second): its q is the full Newton's to
    round-off (the second step is of the order of the first's square) and meets phi = 0;
    q', q'' and lam, through a Jacobian that step away, within 1e-8 of the full Newton's
    (of each one's largest value: measured 1.5e-11 to 1.9e-9), and not the same (the
    full Newton's Jacobian is at q: above 1e-12 where round-off is 1e-15)."""
    system, arrays = _packed_system()
    rng = np.random.default_rng(11)
    nq, m = system.nq, system.active.size
    ints, floats = arrays.packed()
    args = (ints, floats, arrays.functions(0.2), arrays.references(), arrays.bodies())
    on = np.empty(3 * nq + m)
    q, qd = system.design_q(), rng.standard_normal(nq)
    status, _ = project_row(_ends(q, qd), 1.0, 1.0, *args, dense.PROJECTION, on)
    assert status == DONE
    full = dense.PROJECTION.copy()
    full[3] = 0.0  # no exact step taken as converged
    for _ in range(3):
        off = on[:nq] + 3e-10 * rng.standard_normal(nq) / np.sqrt(nq)
        rows = {}
        for name, params in (("one", dense.PROJECTION), ("full", full)):
            rows[name] = np.empty(3 * nq + m)
            status, fresh = project_row(_ends(off, on[nq : 2 * nq]), 1.0, 1.0, *args, params,
                                        rows[name])  # fmt: skip
            assert status == DONE and fresh == 1
        one, other = rows["one"], rows["full"]
        assert np.abs(one[:nq] - other[:nq]).max() < 1e-15
        k = system.kin(one[:nq], one[nq : 2 * nq], 0.2)
        assert np.abs(system.phi(k)).max() < 1e-15
        moved = []
        for lo, hi in ((nq, 2 * nq), (2 * nq, 3 * nq), (3 * nq, 3 * nq + m)):
            moved.append(np.abs(one[lo:hi] - other[lo:hi]).max() / np.abs(other[lo:hi]).max())
        assert max(moved) < 1e-8 and min(moved) > 1e-12


def test_pendulum_with_dense_rows_meets_the_closed_form() -> None:
    """A bar released from the horizontal: the period T = 4 sqrt(I_O / (m g L/2))
    K(sin^2(pi/4)) from the last return to the horizontal among the dense rows (vertex of
    the parabola through three rows), and m g (L/2) sin(theta) + I_O omega^2 / 2 against
    m g L over 3 s."""
    bar = Bar()
    sol = mechlib.solve(
        hinged_bar(bar),
        mechlib.Dynamic(3.0, 0.001, tolerance=1e-8, dense=True),
        requests=list(PENDULUM_REQUESTS),
    )
    assert sol.ok
    period, energy = pendulum_errors(sol, bar)
    assert period < TOL_PERIOD and energy < TOL_ENERGY


def test_conditioning_check() -> None:
    assert _well_conditioned(np.diag([1.0, 1e-6]))
    assert not _well_conditioned(np.diag([1.0, 1e-10]))  # below WELL_CONDITIONED
    assert not _well_conditioned(np.diag([1.0, -1.0]))  # not positive definite
    assert not _well_conditioned(np.array([[1.0, np.nan], [np.nan, 1.0]]))


def test_inverse_mass_in_closed_form() -> None:
    """The kernel's M^-1 blocks, (G^T J'^-1 G / 4 + p p^T / s) / |p|^4 for the Euler
    parameters, times `mass_blocks`' M: the identity to round-off (1e-12), on the
    constraints and off them (|p| = 1.01: the form is exact for any p); its Cholesky factor
    (loops) against LAPACK's."""
    system, arrays = _packed_system()
    rng = np.random.default_rng(5)
    nb, body = system.nq // 7, arrays.bodies()
    _, masses, pscale, inertia = ca.body_terms(body, nb)
    for stretch in (1.0, 1.01):
        q = system.design_q() + 1e-2 * rng.standard_normal(system.nq)
        for b in range(nb):
            q[7 * b + 3 : 7 * b + 7] *= stretch / np.linalg.norm(q[7 * b + 3 : 7 * b + 7])
        x, _ = ca.state_arrays(q, q, nb)
        blocks = np.empty((nb, 7, 7))
        kr.mass_blocks(x, masses, inertia, pscale, blocks)
        inverse = _inverse_mass(x, body, inverse_inertia(body, nb))
        for b in range(nb):
            assert np.abs(inverse[b] @ blocks[b] - np.eye(7)).max() < 1e-12
    a = rng.standard_normal((20, 21))
    a = a @ a.T
    ok, low = _cholesky(a)
    assert ok and np.abs(low - np.linalg.cholesky(a)).max() < 1e-12 * np.abs(low).max()


def test_nu_without_gamma() -> None:
    """`nu_values` is `nu_and_gamma`'s nu: the driven crank's motion rate in its row."""
    jit.compile_all()
    system, arrays, (ints, floats) = _crank_packed()
    m, nb = system.active.size, system.nq // 7
    x, xd = ca.state_arrays(system.design_q(), np.ones(system.nq), nb)
    nu, gamma, alone = np.empty(m), np.empty(m), np.full(m, np.nan)
    functions = arrays.functions(0.4)
    ca.nu_and_gamma(x, xd, ints, floats, functions, arrays.references(), nu, gamma)
    ca.nu_values(ints, floats, functions, alone)
    assert np.abs(nu).max() > 0.0  # the motion's rate
    assert np.array_equal(alone, nu)


def test_gamma_alone_in_a_work_array() -> None:
    """`unpacked_gamma` (the dense rows' and the step's consistent state's gamma, without
    nu, in a reused work array) is the constraint groups' own gamma (Python formulas,
    1e-12 of its largest) on the driven crank at a random velocity, with the work array
    full of NaN before: every row it reads it writes first; `unpacked_nu_values` then
    gives the motion's rate as before."""
    jit.compile_all()
    system, arrays, (ints, floats) = _crank_packed()
    packed = ca.unpack(ints, floats)
    m, nb = system.active.size, system.nq // 7
    rng = np.random.default_rng(11)
    q, qd = system.design_q(), rng.standard_normal(system.nq)
    k = system.kin(q, qd, 0.4)
    parts = [g.gamma(k) for g in system.groups] + [system.coordinate_rows().gamma(k)]
    want = np.concatenate(parts)[np.asarray(system.active)]
    x, xd = ca.state_arrays(q, qd, nb)
    functions = arrays.functions(0.4)
    gamma, work = np.full(m, np.nan), np.full(ca.row_count_unpacked(packed), np.nan)
    ca.unpacked_gamma(x, xd, packed, functions, arrays.references(), gamma, work)
    assert np.abs(gamma - want).max() <= 1e-12 * np.abs(want).max()
    nu = np.full(m, np.nan)
    ca.unpacked_nu_values(packed, functions, nu)
    assert np.array_equal(nu, system.nu(k))


def test_factored_reads_the_lower_triangle_only() -> None:
    """`_factored` checks finiteness where it reads (the lower triangle, the products'
    upper triangles stay zero): a NaN there refuses the matrix, one above it does not."""
    a = np.array([[4.0, 0.0], [2.0, 3.0]])
    low = np.zeros((2, 2))
    assert _factored(a, low)
    a[0, 1] = np.nan
    assert _factored(a, low)
    a[1, 0] = np.nan
    assert not _factored(a, low)


def test_a_steps_rows_take_their_constants_once() -> None:
    """A step's rows in one call (the constraints unpacked and each body's J'^-1 taken
    once for all of them) are the rows of one call each, bit for bit; J'^-1 times J' is
    the identity to round-off (1e-12); a body without rotary inertia has no J'^-1 and its
    rows go back to Python (FALLBACK) rather than divide by zero."""
    system, arrays = _packed_system()
    rng = np.random.default_rng(7)
    nq, m, nb = system.nq, system.active.size, system.nq // 7
    q0 = system.design_q() + 1e-4 * rng.standard_normal(nq)
    ends = np.stack([q0, *rng.standard_normal((2, nq)), q0 + 1e-3, *rng.standard_normal((2, nq))])
    ints, floats = arrays.packed()
    times = np.array([0.1e-3, 0.4e-3, 0.9e-3, 1e-3])
    together, z = np.empty((len(times), 3 * nq + m)), np.empty((len(times), 0))
    args = (ints, floats, arrays.functions(0.0), arrays.references(), arrays.bodies())
    done, _ = project_loaded_rows(
        ends, 0.0, 1e-3, times, *args, dense.PROJECTION, np.zeros((4, 0)), no_forces(),
        together, z,
    )  # fmt: skip
    assert done == len(times)
    for k, t in enumerate(times):
        alone = np.empty(3 * nq + m)
        s = 1.0 if t == times[-1] else t / 1e-3
        status, _ = project_loaded_row(
            ends, 1e-3, s, *args, dense.PROJECTION, np.zeros(0), no_forces(), alone
        )
        assert status == DONE and np.array_equal(alone, together[k])
    body = arrays.bodies()
    _, _, _, inertia = ca.body_terms(body, nb)
    for b, inverse in enumerate(inverse_inertia(body, nb)):
        assert np.abs(inverse @ inertia[b] - np.eye(3)).max() < 1e-12
    flat = body.copy()
    flat[3 + 2 * nb : 3 + 2 * nb + 9] = 0.0  # the first body's inertia tensor
    assert inverse_inertia(flat, nb).shape == (0, 3, 3)
    out = np.empty(3 * nq + m)
    status, _ = project_row(ends, 1e-3, 0.5, *args[:-1], flat, dense.PROJECTION, out)
    assert status == FALLBACK


def test_the_kernel_gives_up_and_python_takes_the_row() -> None:
    """A non-finite interpolated state: the kernel says FALLBACK (it never returns a
    row it could not check), and `projected_row` goes to the Python path."""
    system, arrays = _packed_system()
    nq = system.nq
    q = system.design_q()
    q[0] = np.nan
    out = np.empty(3 * nq + system.active.size)
    ints, floats = arrays.packed()
    ends = _ends(q, np.zeros(nq))
    status, _ = project_row(
        ends, 1.0, 1.0, ints, floats, arrays.functions(0.0), arrays.references(),
        arrays.bodies(), dense.PROJECTION, out,
    )  # fmt: skip
    assert status == FALLBACK
    assert dense._compiled_row(system, 0.0, ends, 1.0, 1.0) is None


def test_interpolant_in_the_kernel_is_the_quintic_hermite() -> None:
    """`interpolated` against the quintic through both ends' (q, qd, qdd), evaluated from
    its closed form (exact to round-off: 1e-12), and the end's own state at s = 1."""
    jit.compile_all()
    c = np.array([0.3, -1.2, 0.7, 2.0, -0.5, 0.25])  # q(t) = sum c_i t^i

    def q(t):
        return sum(ci * t**i for i, ci in enumerate(c))

    def qd(t):
        return sum(i * ci * t ** (i - 1) for i, ci in enumerate(c) if i)

    def qdd(t):
        return sum(i * (i - 1) * ci * t ** (i - 2) for i, ci in enumerate(c) if i > 1)

    t0, t1 = 0.4, 1.1
    ends = np.array([[f(t)] for t in (t0, t1) for f in (q, qd, qdd)])
    for s in (0.0, 0.25, 0.6, 0.999):
        t = t0 + s * (t1 - t0)
        got_q, got_qd = interpolated(ends, t1 - t0, s)
        assert abs(got_q[0] - q(t)) < 1e-12 and abs(got_qd[0] - qd(t)) < 1e-12
    at_end = interpolated(ends + 1e-3, t1 - t0, 1.0)  # not a quintic: the end as given
    assert at_end[0][0] == ends[3, 0] + 1e-3 and at_end[1][0] == ends[4, 0] + 1e-3


@pytest.mark.parametrize("model", [_free_crank, _driven_crank], ids=["free", "driven"])
def test_rows_products_over_the_blocks_they_touch(model) -> None:
    """The rows' products skip the Jacobian's blocks a row does not touch (`row_work`'s
    `touched`): at a random state every entry outside them is zero, and the products over
    the touched blocks are the full products bit for bit (the sums left out are zeros)
    and numpy's to round-off (1e-13 of the largest)."""
    jit.compile_all()
    mech, _, _ = model()
    system = System(mech)
    arrays = system.packed_constraints()
    assert arrays is not None
    ints, floats = arrays.packed()
    nq, m, nb = system.nq, system.active.size, system.nq // 7
    work = row_work(ints, floats, arrays.bodies(), nq, m)
    packed, touched = work[0], work[11]
    rng = np.random.default_rng(11)
    x, _ = ca.state_arrays(system.design_q() + 0.1 * rng.standard_normal(nq), np.zeros(nq), nb)
    phi, jac = np.empty(m), np.empty((m, nq))
    ca.phi_and_jacobian_in(x, packed, arrays.functions(0.3), arrays.references(), phi, jac,
                           work[9], work[10])  # fmt: skip
    assert touched.shape == (m, nb) and 0 < touched.sum() < m * nb  # the crank's rows: sparse
    outside = np.repeat(~touched, 7, axis=1)
    assert np.abs(jac[outside]).max() == 0.0 and np.abs(jac[~outside]).max() > 0.0
    every = np.ones_like(touched)
    v, y = rng.standard_normal(nq), rng.standard_normal(m)
    products = []
    for blocks in (touched, every):
        square, out_m, out_q = np.zeros((m, m)), np.empty(m), np.empty(nq)
        _lower_product(jac, jac, blocks, square)
        _times(jac, v, blocks, out_m)
        _transpose_times(jac, y, blocks, out_q)
        products.append((square, out_m, out_q))
    for ours, full in zip(*products, strict=True):
        assert np.array_equal(ours, full)
    square, out_m, out_q = products[0]
    for ours, exact in ((square, np.tril(jac @ jac.T)), (out_m, jac @ v), (out_q, jac.T @ y)):
        assert np.abs(ours - exact).max() <= 1e-13 * np.abs(exact).max()
