"""Forward-difference columns and modal bodies (mechlib.system.fd_columns): a modal body's
forces are left out of the columns of the bodies they do not read (its frame, and with
geometric stiffening its node bodies, are read) and of the other modal bodies' modes. Each
column's difference equals, bit for bit, the one with every modal body evaluated: the forces
left out are equal at the base and the perturbed state, so the sums differ by nothing.

Model: two of Kane's beams (4 elements, 3 modes, root and tip kept), one stiffened and one
not, each on its own hub, bent and turning, with random weld multipliers (the stiffened
beam's node loads read them)."""

from __future__ import annotations

import numpy as np

import mechlib
from mechlib.flexible.craig_bampton import craig_bampton
from mechlib.system.fd_columns import ColumnSkips
from mechlib.system.system import System

from .test_flexible_stiffening import SpinUp, _beam

STEP = 1e-7


def _two_beams() -> tuple[System, np.ndarray, np.ndarray, np.ndarray]:
    m = mechlib.Mechanism()
    for name, stiff, y in (("stiff", True, 0.0), ("plain", False, 3.0)):
        comp = craig_bampton(
            _beam(4), damping=0.01, fixed_interface_modes=3, keep_nodes=(4,), stiffening=stiff
        )
        m.add_flexible_body(name, comp, at=(0.0, y, 0.0))
        hub = f"hub_{name}"
        m.add_joint(hub, "revolute", bodies=(name, "ground"), at=(0, y, 0), axis=(0, 0, 1))
        m.add_motion(f"spin_{name}", joint=hub, function=SpinUp(4.0))
    system = System(m)
    rng = np.random.default_rng(3)
    q = system.design_q()
    q[7 * system.nb :] = rng.normal(scale=0.05, size=system.nz)
    qd = rng.normal(scale=0.5, size=system.nq)
    lam = rng.normal(scale=500.0, size=system.active.size)
    return system, q, qd, lam


def test_columns_without_the_modal_bodies_they_cannot_change():
    system, q, qd, lam = _two_beams()
    skips = ColumnSkips(system)
    left_out = 0
    for j in range(system.nq):
        skip = skips.skip(skips.body(j))
        left_out += len(skip)
        for moved in (q, qd):
            step = np.zeros(system.nq)
            step[j] = STEP
            k = system.kin(q, qd, 1.0)
            kp = system.kin(q + step, qd, 1.0) if moved is q else system.kin(q, qd + step, 1.0)
            every = system.forces(kp, lam=lam) - system.forces(k, lam=lam)
            some = system.forces(kp, lam=lam, skip=skip) - system.forces(k, lam=lam, skip=skip)
            np.testing.assert_array_equal(some, every)
    assert left_out > system.nq  # most columns leave a beam out


def _tangents(system, q, qd, lam, every: bool):
    """The integrator's differenced (K, C), with the inert columns skipped or (`every`)
    each evaluated."""
    import mechlib.solvers.genalpha.integrator as module
    from mechlib.core.outcome import SolverStats

    integrator = module.Integrator(system, mechlib.Dynamic(end=1.0, step=0.1), SolverStats())
    k = system.kin(q, qd, 1.0)
    original = ColumnSkips.inert
    try:
        if every:
            ColumnSkips.inert = lambda self, body: False  # type: ignore[method-assign]
        return integrator._differenced_tangent(k, [], lam, system.phi_q(k), 1e-3)
    finally:
        ColumnSkips.inert = original  # type: ignore[method-assign]


def test_inert_columns_are_the_massless_nodes_nothing_reads():
    """The plain beam's node bodies (root and tip: only joints and welds touch them) are
    inert; the stiffened beam's are read by its stiffening, the frames by their modal
    bodies; the tangent that skips the inert columns equals, bit for bit, the one that
    evaluates them, where they are exactly zero."""
    system, q, qd, lam = _two_beams()
    skips = ColumnSkips(system)
    stiff, plain = system.flexible
    inert = {b for b in range(system.nb) if skips.inert(b)}
    assert inert == set(plain.nodes)
    assert not inert & ({stiff.frame, plain.frame} | set(stiff.nodes))
    fast = _tangents(system, q, qd, lam, every=False)
    full = _tangents(system, q, qd, lam, every=True)
    columns = np.concatenate([np.arange(7 * b, 7 * b + 7) for b in sorted(inert)])
    for mine, reference in zip(fast, full):
        np.testing.assert_array_equal(mine, reference)
        assert not reference[:, columns].any()
        assert np.abs(reference).max() > 0.0


def test_a_loaded_or_massive_node_is_not_inert():
    """A force element on a node body, or a body with mass, makes its columns count."""
    m = mechlib.Mechanism()
    comp = craig_bampton(_beam(4), damping=0.01, fixed_interface_modes=3, keep_nodes=(4,))
    m.add_flexible_body("beam", comp)
    m.add_joint("hub", "revolute", bodies=("beam", "ground"), at=(0, 0, 0), axis=(0, 0, 1))
    m.add_body("weight", mass=1.0, cm=(0.0, 5.0, 0.0), inertia=[1e-3] * 3)
    m.add_joint("held", "spherical", bodies=("weight", "ground"), at=(0.0, 5.0, 0.0))
    m.add_force(mechlib.Spring("pull", (("beam", (10.0, 0, 0)), ("ground", (10.0, 1.0, 0))), 10.0))
    system = System(m)
    skips = ColumnSkips(system)
    (beam,) = system.flexible
    root, tip = beam.nodes
    assert skips.inert(root)
    assert not skips.inert(tip)  # the spring reads it
    assert not skips.inert(system.body_index("weight"))  # its mass
