"""Exudyn's side of the flexible bench (benchmarks.flexible_exudyn): the reduced FFRF body
gets `loads`'s own inertia invariants and modes, its first frequencies held at the hub match
Euler-Bernoulli's clamped beam (3.516 and 22.03 sqrt(E I / (rho A L^4))), and its tip lag
follows `loads`'s within the measured difference of the converged runs (1.3e-3 of range);
the flexible slider-crank's rod is `loads`'s component and its slider follows `loads`'s."""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pytest

from benchmarks.ffrf_exudyn import ffrf_terms
from benchmarks.flexible import KANE_MODES, kane_beam
from mechlib.flexible.craig_bampton import craig_bampton

needs_exudyn = pytest.mark.skipif(
    importlib.util.find_spec("exudyn") is None,
    reason="Exudyn not installed (pip install -e '.[bench]')",
)

EI, RHO_A, LENGTH = 1.4e4, 1.2, 10.0  # N m^2, kg/m, m
CLAMPED = (1.8751040687, 4.6940911330)  # beta_k L of a clamped-free beam


def _clamped(k: int) -> float:
    """Euler-Bernoulli's k-th clamped-free frequency (rad/s)."""
    return CLAMPED[k] ** 2 * math.sqrt(EI / (RHO_A * LENGTH**4))


def test_ffrf_terms_are_the_loads_invariants():
    model = kane_beam()
    terms = ffrf_terms(model, KANE_MODES)
    comp = craig_bampton(model, damping=0.0, fixed_interface_modes=4)
    inv, n = comp.invariants, comp.count
    np.testing.assert_allclose(terms.omega, comp.frequencies, rtol=1e-12)
    assert terms.mass == pytest.approx(inv.I1, rel=1e-12) and terms.mass == pytest.approx(12.0)
    np.testing.assert_allclose(terms.center_of_mass, 0.0, atol=1e-12)
    scale = np.abs(inv.I7).max()
    np.testing.assert_allclose(terms.inertia, inv.I7, atol=1e-12 * scale)
    np.testing.assert_allclose(terms.mass_reduced, np.eye(n), atol=1e-10)
    np.testing.assert_allclose(
        terms.stiffness_reduced, np.diag(comp.stiffness), atol=1e-9 * comp.stiffness.max()
    )
    np.testing.assert_allclose(terms.m_xref_tilde_psi, -inv.I4, atol=1e-9)
    np.testing.assert_allclose(terms.m_phit_t_psi, inv.I3, atol=1e-9)
    for j in range(n):
        np.testing.assert_allclose(terms.m_psi_tilde_psi[3 * j : 3 * j + 3], -inv.I5[j], atol=1e-9)
        np.testing.assert_allclose(
            terms.m_xref_tilde_psi_tilde[:, 3 * j : 3 * j + 3], -inv.I8[j], atol=1e-9
        )
        for k in range(n):
            block = terms.m_psi_tilde_psi_tilde[3 * j : 3 * j + 3, 3 * k : 3 * k + 3]
            np.testing.assert_allclose(block, -inv.I9[j, k], atol=1e-9)


@needs_exudyn
@pytest.mark.parametrize("joint", ["weld", "marker"])
def test_exudyn_beam_held_at_the_hub_has_the_clamped_frequencies(joint):
    from benchmarks.flexible_exudyn import build_kane_exudyn

    built = build_kane_exudyn(0.01, joint=joint)
    w2 = np.sort(np.asarray(built.mbs.ComputeODE2Eigenvalues()[0]))
    omega = np.sqrt(w2)
    assert len(omega) == 4  # two bending planes, two modes each; the hub holds the rest
    # 6 cubic elements: measured 4e-6 (first) and 2e-4 (second) from the closed form
    assert omega[0] == pytest.approx(_clamped(0), rel=1e-4)
    assert omega[1] == pytest.approx(_clamped(0), rel=1e-4)
    assert omega[2] == pytest.approx(_clamped(1), rel=1e-3)
    held = craig_bampton(kane_beam(), damping=0.0, fixed_interface_modes=4).held_frequency
    assert omega[0] == pytest.approx(held, rel=1e-6)


@needs_exudyn
def test_exudyn_tip_lag_follows_loads():
    from benchmarks.flexible import _run
    from benchmarks.flexible_exudyn import run_kane_exudyn

    sol, lag, _ = _run("kane_plain", 1e-6)  # 9.4e-4 of range from its run at 1e-8
    run = run_kane_exudyn(0.005)  # 1.3e-4 from its run at 0.0025 s
    np.testing.assert_allclose(run.time, sol.time, atol=1e-9)
    span = np.ptp(lag)
    assert span == pytest.approx(0.434, abs=0.002)  # m: peak lag -0.432 m near 8 s
    # measured 1.9e-3: the converged runs differ by 1.3e-3 (loads at 1e-8, Exudyn at 0.625 ms)
    assert np.abs(run.signal - lag).max() / span < 2.5e-3


def test_crank_rod_terms_are_the_loads_component():
    from benchmarks.flexible import ROD_MODES, flexible_slider_crank, slider_crank_rod

    terms = ffrf_terms(slider_crank_rod(), ROD_MODES)
    comp = flexible_slider_crank().flexible["rod"].component
    np.testing.assert_allclose(terms.omega, comp.frequencies, rtol=1e-10)
    np.testing.assert_allclose(terms.inertia, comp.invariants.I7, atol=1e-12)
    assert terms.mass == pytest.approx(comp.mass, rel=1e-12)


@needs_exudyn
def test_exudyn_slider_crank_follows_loads():
    from benchmarks.flexible import _run
    from benchmarks.flexible_exudyn_crank import run_crank_exudyn

    sol, x, _ = _run("slider_crank", 1e-5)  # 2.8e-4 of range from its run at 1e-8
    run = run_crank_exudyn(2e-4)  # 2.9e-4 from loads at 1e-8 (6e-5 at 12.5 us)
    np.testing.assert_allclose(run.time, sol.time, atol=1e-12)
    span = np.ptp(x)
    assert span == pytest.approx(0.3, abs=1e-3)  # m: the crank's stroke, 2 x 0.15
    assert np.abs(run.signal - x).max() / span < 5e-4  # measured 2.5e-4


def _lumped_kane_beam():
    """Kane's FE beam with its mass lumped (the translations' row sums, the rotations'
    diagonal): no mass couples translations and rotations."""
    import dataclasses

    import scipy.sparse as sp

    model = kane_beam()  # this module's name: the original, not the patched one
    mass, gamma = model.mass.tocsr(), model.translation_field()
    sums = np.asarray(mass @ gamma)
    comps = model.dof_map[:, 1]
    diag = np.where(comps < 3, sums[np.arange(len(comps)), np.minimum(comps, 2)], mass.diagonal())
    return dataclasses.replace(model, mass=sp.diags(diag).tocsc())


@needs_exudyn
def test_codes_agree_when_no_mass_couples_translations_and_rotations(monkeypatch):
    """With the consistent beam mass the converged codes differ by 1.3e-3 of the range:
    `loads` couples the frame's rotation and translation through c = I2 + I3 zeta (the
    deformation's first moment, rotational DOF included), Exudyn's object through
    Phit^T M PsiTilde (the translations' alone): 0.15-0.34 kg^0.5 m here where I3 = 0.
    Lumped, the two are one and the codes agree: measured 2.9e-5 (loads at 1e-8), 1.3e-4
    (loads at 1e-7, Exudyn at 1.25 ms)."""
    import benchmarks.flexible as flexible
    import benchmarks.flexible_exudyn as flexible_exudyn

    monkeypatch.setattr(flexible, "kane_beam", _lumped_kane_beam)
    monkeypatch.setattr(flexible_exudyn, "kane_beam", _lumped_kane_beam)
    terms = ffrf_terms(_lumped_kane_beam(), KANE_MODES)
    assert np.abs(terms.m_phit_t_psi_tilde).max() < 1e-12
    _, lag, _ = flexible._run("kane_plain", 1e-7)
    run = flexible_exudyn.run_kane_exudyn(0.0025)
    assert np.abs(run.signal - lag).max() / np.ptp(lag) < 3e-4
