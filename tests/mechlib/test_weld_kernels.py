"""The compiled weld equations of a modal body's kept nodes (mechlib.flexible.weld_kernels)
against differences of their residual: Jacobian = dphi/dq, rate = phi_q qd, gamma = -(the
rate's change along the motion at qdd = 0), at a random bent, turning state of Kane's beam
(root and tip nodes kept, 3 modes)."""

from __future__ import annotations

import numpy as np

from .test_stiffening_reactions import _spinning_system

STEP = 1e-6  # central differences: truncation ~ STEP^2, round-off ~ 1e-16 / STEP


def _state():
    system, k, _ = _spinning_system(True)
    q, qd = system.state_of(k)
    rng = np.random.default_rng(5)
    q = q + rng.normal(scale=0.05, size=q.size)
    qd = qd + rng.normal(scale=0.5, size=q.size)
    assert system._welds is not None
    welds, _ = system._welds
    return system, welds, q, qd


def _column(system, j: int) -> int:
    """The working Jacobian's column (ground's seven included) of coordinate j of q."""
    return j if j < 7 * system.nb else j + 7


def test_weld_jacobian_is_the_derivative_of_the_residual():
    """Each column within 1e-8 of the largest entry (measured 8e-11)."""
    system, welds, q, qd = _state()
    k = system.kin(q, qd, 1.0)
    jac = np.zeros((welds.size, k.ncol))
    welds.jacobian(k, jac)
    scale = np.abs(jac).max()
    for j in range(system.nq):
        dq = np.zeros(system.nq)
        dq[j] = STEP
        up, down = welds.phi(system.kin(q + dq, qd, 1.0)), welds.phi(system.kin(q - dq, qd, 1.0))
        assert np.abs(jac[:, _column(system, j)] - (up - down) / (2 * STEP)).max() < 1e-8 * scale


def test_weld_rate_and_gamma_follow_the_motion():
    """rate = phi_q qd (1e-12 of its largest entry, measured 5e-17); gamma = -d(rate)/dt
    along q + s qd at fixed qd (central differences, within 1e-7 of its largest entry,
    measured 2e-10)."""
    system, welds, q, qd = _state()
    k = system.kin(q, qd, 1.0)
    jac = np.zeros((welds.size, k.ncol))
    welds.jacobian(k, jac)
    working = np.zeros(k.ncol)
    working[[_column(system, j) for j in range(system.nq)]] = qd
    rate = welds.rate(k)
    assert np.abs(rate - jac @ working).max() < 1e-12 * np.abs(rate).max()
    up = welds.rate(system.kin(q + STEP * qd, qd, 1.0))
    down = welds.rate(system.kin(q - STEP * qd, qd, 1.0))
    gamma = welds.gamma(k)
    assert np.abs(gamma + (up - down) / (2 * STEP)).max() < 1e-7 * np.abs(gamma).max()
