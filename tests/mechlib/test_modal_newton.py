"""The compiled Newton loop for systems with modal bodies
(mechlib.solvers.genalpha.modal_newton, .modal_step; mechlib.flexible.packed) against the
Python step it replaces.

- Its parts at a random deformed, moving state of the flexible slider-crank
  (benchmarks.flexible: a rigid crank and slider, a rod of 34 modes welded at both ends) and
  of Kane's stiffened beam (random weld multipliers load its stiffening): the constraint
  residual and Jacobian, M qdd + phi_q^T lam - Q, gamma and the matrices factored (M,
  phi_q) equal System's to round-off
  (1e-12 of each array's largest entry: the same kernels summed in another order).
- Whole runs: Kane's beam (unstiffened and stiffened, 4 s at 1e-6) and the slider-crank
  (0.02 s at 1e-4) take the same steps, rejections and Newton iterations compiled as in
  Python (`compiled: python`), and the compared signals differ by round-off (measured at
  most 2e-12 of their range over the bench's full runs; bound 1e-9).
"""

from __future__ import annotations

import numpy as np
import pytest

import mechlib
from benchmarks.flexible import _kane_lag, flexible_slider_crank, spin_up_beam
from mechlib.core.outcome import SolverStats
from mechlib.flexible.packed import modal_arrays
from mechlib.kinematics import constraint_arrays as ca
from mechlib.solvers.genalpha import modal_newton as mn
from mechlib.solvers.genalpha.integrator import Integrator
from mechlib.system.system import System

ROUNDOFF = 1e-12


def _state(system: System, seed: int):
    rng = np.random.default_rng(seed)
    q = system.design_q()
    q[7 * system.nb :] = 1e-3 * rng.standard_normal(system.nz)
    qd = rng.standard_normal(system.nq)
    qdd = rng.standard_normal(system.nq)
    lam = 100.0 * rng.standard_normal(system.active.size)
    return q, qd, qdd, lam


def _close(mine: np.ndarray, reference: np.ndarray) -> None:
    assert np.abs(mine - reference).max() <= ROUNDOFF * max(1.0, np.abs(reference).max())


@pytest.mark.parametrize("model", ["crank", "stiffened beam"])
def test_kernels_equal_the_system(model):
    mech = flexible_slider_crank() if model == "crank" else spin_up_beam(True)
    mechlib.solve(mech, mechlib.Dynamic(end=1e-4, step=1e-4), requests=[])  # kernels compiled
    system = System(mech)
    arrays = modal_arrays(system)
    assert arrays is not None
    q, qd, qdd, lam = _state(system, 5)
    nb, nq, t = system.nb, system.nq, 0.3
    k = system.kin(q, qd, t)
    ints, floats = arrays.packed()
    packed = ca.unpack(ints, floats)
    bodies, welds, active = arrays.modal(), arrays.welds(), arrays.active()
    functions, refs = arrays.functions(t), arrays.references()
    nall = packed[25].shape[0] + welds[1]
    full, rows = np.empty(nall), np.empty((nall, nq + 7))
    x, xd = ca.state_arrays(q, qd, nb)
    mn.modal_rows(x, q[7 * nb :], packed, functions, refs, bodies, welds, full, rows)
    phi, jac = system.phi_and_jacobian(k)
    _close(full[active], phi)
    _close(system.body_columns(rows[active]), jac)
    work = (np.empty((3, nq)), np.empty(nall), np.zeros((nb + 1, 3)))
    out = np.empty(nq + lam.size)
    mn._residual(x, xd, q, qd, qdd, lam, rows, active, arrays.bodies(), bodies, work, out)
    reference = system.mass(k) @ qdd + jac.T @ lam - system.forces(k, lam=lam, jac=jac)
    _close(out[:nq], reference)
    nu, gamma = np.empty(lam.size), np.empty(lam.size)
    mn._nu_and_gamma(x, xd, q, qd, packed, functions, refs, bodies, welds, active, nu, gamma)
    _close(nu, system.nu(k))
    _close(gamma, system.gamma(k))
    mass, phi_q = np.empty((nq, nq)), np.empty((lam.size, nq))
    args = (ints, floats, functions, refs, arrays.bodies(), bodies, welds, active)
    mn.modal_matrices(q, *args, mass, phi_q)
    _close(mass, system.mass(k))
    _close(phi_q, jac)


def _run(name: str, compiled: str) -> tuple[mechlib.Solution, np.ndarray]:
    if name == "crank":
        mech, end, step, tol = flexible_slider_crank(), 0.02, 1e-3, 1e-4
        requests = [mechlib.PointKinematics("slider", "slider")]
    else:
        mech, end, step, tol = spin_up_beam(name == "stiffened"), 4.0, 0.1, 1e-6
        requests = [mechlib.PointKinematics("tip", "tip")]
    spec = mechlib.Dynamic(end=end, step=step, tolerance=tol, compiled=compiled)
    sol = mechlib.solve(mech, spec, requests=requests)
    assert sol.ok, sol.message
    signal = sol.channels["slider.x"] if name == "crank" else _kane_lag(sol)
    return sol, np.asarray(signal)


@pytest.mark.parametrize("name", ["plain", "stiffened", "crank"])
def test_runs_equal_the_python_step(name):
    fast, fast_signal = _run(name, "steps")
    slow, slow_signal = _run(name, "python")
    for field in ("steps", "rejected_steps", "newton_iterations"):
        assert getattr(fast.stats, field) == getattr(slow.stats, field), field
    assert np.abs(fast_signal - slow_signal).max() <= 1e-9 * np.ptp(slow_signal)


def test_the_compiled_loop_is_the_one_taken():
    system = System(spin_up_beam(False))
    mechlib.solve(spin_up_beam(False), mechlib.Dynamic(end=1e-4, step=1e-4), requests=[])
    assert Integrator(system, mechlib.Dynamic(end=1.0, step=0.1), SolverStats()).modal is not None
    python = mechlib.Dynamic(end=1.0, step=0.1, compiled="python")
    assert Integrator(system, python, SolverStats()).modal is None
    loaded = spin_up_beam(False)
    loaded.add_force(mechlib.Spring("pull", (("beam", (10.0, 0, 0)), ("ground", (10, 1, 0))), 1.0))
    assert modal_arrays(System(loaded)) is None  # a force element: the Python step
