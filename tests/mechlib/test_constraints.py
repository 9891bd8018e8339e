"""Constraint primitives (Spherical, Dot1, Dot2, Normalization) against finite differences.

Definitions checked (Haug 1989, ch. 9-11): `jacobian` is d(phi)/dx over all 7 (nb+1)
columns (ground last); `rate` is d(phi)/dt along x(t) = x + t xd; `gamma` is what
phi_q qdd = gamma must equal for the second derivative of phi to vanish, i.e. along
x(t) = x + t xd + t^2/2 xdd:  d2 phi/dt2 (0) = phi_q xdd - gamma.
All derivatives are taken on the raw (homogeneous) primitives, so the identities hold for
any x, xd, xdd; the test uses unit quaternions and arbitrary rates.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from mechlib.core.rotation import rotation_matrix
from mechlib.kinematics import kernels as kr
from mechlib.kinematics.constraints import Dot1, Dot2, Normalization, Spherical
from mechlib.kinematics.kin import Kin

NB = 3  # moving bodies; ground is index NB
BODY_I = [0, 2, NB, 1]  # pairs include the ground on either side
BODY_J = [1, NB, 0, 2]


def _random_state(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """q (unit quaternions), qd and qdd (arbitrary), each (7 NB,)."""
    x = rng.normal(size=(NB, 7))
    x[:, 3:] /= np.linalg.norm(x[:, 3:], axis=1, keepdims=True)
    return x.ravel(), rng.normal(size=7 * NB), rng.normal(size=7 * NB)


def _primitives(rng: np.random.Generator) -> dict[str, object]:
    k = len(BODY_I)

    def vecs() -> np.ndarray:
        """k body-fixed vectors of any length."""
        return rng.normal(size=(k, 3))

    return {
        "spherical": Spherical(BODY_I, BODY_J, vecs(), vecs()),
        "dot1": Dot1(BODY_I, BODY_J, vecs(), vecs()),
        "dot2": Dot2(BODY_I, BODY_J, vecs(), vecs(), vecs()),
        "normalization": Normalization(NB),
    }


KINDS = ["spherical", "dot1", "dot2", "normalization"]


@pytest.fixture()
def rng() -> np.random.Generator:
    """A seeded generator: the random samples are the same on every run."""
    return np.random.default_rng(7)


def _phi_along(
    prim, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray
) -> Callable[[float], np.ndarray]:
    """t -> phi(q + t qd + t^2/2 qdd) (ground fixed)."""
    return lambda t: prim.phi(Kin.from_state(q + t * qd + 0.5 * t * t * qdd))


def _second_derivative(f: Callable[[float], np.ndarray], step: float = 1e-3) -> np.ndarray:
    """f''(0) by central differences with one Richardson extrapolation (error O(step^4))."""

    def d(h: float) -> np.ndarray:
        return (f(h) - 2.0 * f(0.0) + f(-h)) / (h * h)

    return (4.0 * d(step / 2) - d(step)) / 3.0


@pytest.mark.parametrize("kind", KINDS)
def test_jacobian_matches_central_differences(kind: str, rng: np.random.Generator) -> None:
    """phi_q (ground columns included) against central differences of phi with step 1e-6.
    Truncation ~ step^2 * (4th-degree polynomial derivatives) ~ 1e-11 and round-off
    ~ 1e-16 / 1e-6: tolerance 1e-6 relative to the largest entry (brief)."""
    prim = _primitives(rng)[kind]
    q, _, _ = _random_state(rng)
    k = Kin.from_state(q)
    jac = np.zeros((prim.size, k.ncol))
    prim.jacobian(k, jac)
    fd = np.zeros_like(jac)
    step = 1e-6
    for c in range(k.ncol):
        plus, minus = Kin(k.x.copy(), k.xd.copy()), Kin(k.x.copy(), k.xd.copy())
        plus.x.reshape(-1)[c] += step
        minus.x.reshape(-1)[c] -= step
        fd[:, c] = (prim.phi(plus) - prim.phi(minus)) / (2.0 * step)
    assert np.abs(jac - fd).max() <= 1e-6 * np.abs(fd).max()
    if kind != "normalization":
        assert np.abs(jac[:, 7 * NB :]).max() > 0.0, "ground columns must be filled too"


@pytest.mark.parametrize("kind", KINDS)
def test_gamma_is_the_second_derivative_remainder(kind: str, rng: np.random.Generator) -> None:
    """d2/dt2 phi(q + t qd + t^2/2 qdd) at t = 0 equals phi_q qdd - gamma(q, qd).
    Second derivative by central differences (step 1e-3, Richardson): phi is a polynomial
    of degree <= 8 in t, leaving ~1e-12; round-off ~1e-16 / 1e-6. Tolerance 1e-7 relative
    to the size of the terms."""
    prim = _primitives(rng)[kind]
    q, qd, qdd = _random_state(rng)
    k = Kin.from_state(q, qd)
    jac = np.zeros((prim.size, k.ncol))
    prim.jacobian(k, jac)
    predicted = jac[:, : 7 * NB] @ qdd - prim.gamma(k)
    measured = _second_derivative(_phi_along(prim, q, qd, qdd))
    scale = max(np.abs(prim.gamma(k)).max(), np.abs(jac[:, : 7 * NB] @ qdd).max())
    assert np.abs(predicted - measured).max() <= 1e-7 * scale


@pytest.mark.parametrize("kind", ["dot1", "dot2"])
def test_rate_matches_finite_differences(kind: str, rng: np.random.Generator) -> None:
    """rate = d(phi)/dt along q + t qd = phi_q qd; central differences with step 1e-6
    (truncation ~1e-12, round-off ~1e-10): tolerance 1e-8 relative."""
    prim = _primitives(rng)[kind]
    q, qd, _ = _random_state(rng)
    k = Kin.from_state(q, qd)
    f = _phi_along(prim, q, qd, np.zeros_like(qd))
    step = 1e-6
    fd = (f(step) - f(-step)) / (2.0 * step)
    scale = np.abs(fd).max()
    assert np.abs(prim.rate(k) - fd).max() <= 1e-8 * scale
    jac = np.zeros((prim.size, k.ncol))
    prim.jacobian(k, jac)
    assert np.abs(prim.rate(k) - jac[:, : 7 * NB] @ qd).max() <= 1e-12 * scale


def test_spherical_residual_is_the_point_gap(rng: np.random.Generator) -> None:
    """Spherical phi = (r_i + A_i s_i) - (r_j + A_j s_j), written out with
    A(p) from mechlib.core.rotation (1e-14)."""
    q, _, _ = _random_state(rng)
    si, sj = rng.normal(size=(1, 3)), rng.normal(size=(1, 3))
    k = Kin.from_state(q)
    phi = Spherical([0], [NB], si, sj).phi(k)
    expected = k.r[0] + rotation_matrix(k.p[0]) @ si[0] - sj[0]
    assert np.abs(phi - expected).max() < 1e-14


def test_normalization_values(rng: np.random.Generator) -> None:
    """Normalization: phi = |p|^2 - 1 (zero for unit p), gamma = -2 |pd|^2 (1e-14)."""
    q, qd, _ = _random_state(rng)
    k = Kin.from_state(q, qd)
    norm = Normalization(NB)
    assert np.abs(norm.phi(k)).max() < 1e-14
    expected = -2.0 * np.sum(qd.reshape(NB, 7)[:, 3:] ** 2, axis=1)
    assert np.abs(norm.gamma(k) - expected).max() < 1e-14


@pytest.mark.parametrize("kind", ["dot1", "dot2"])
def test_residual_and_jacobian_in_one_loop_equal_the_two_kernels(
    kind: str, rng: np.random.Generator
) -> None:
    """kernels.dot1_phi_jac / dot2_phi_jac (the packed rows' one loop, each row's arms taken
    once) give the residuals of dot1_phi / dot2_phi and the rows of dot1_jac / dot2_jac bit
    for bit, added into rows that already hold values (the Jacobian kernels add)."""
    k = len(BODY_I)
    bi, bj = np.array(BODY_I), np.array(BODY_J)
    u, v, w = (rng.normal(size=(k, 3)) for _ in range(3))
    args = (bi, bj, u, v) if kind == "dot1" else (bi, bj, u, v, w)
    kernels: dict[str, tuple[Callable[..., None], ...]] = {
        "dot1": (kr.dot1_phi, kr.dot1_jac, kr.dot1_phi_jac),
        "dot2": (kr.dot2_phi, kr.dot2_jac, kr.dot2_phi_jac),
    }
    phi_of, jac_of, both = kernels[kind]
    for _ in range(5):
        q, _, _ = _random_state(rng)
        x = Kin.from_state(q).x
        start = rng.normal(size=(k, 7 * (NB + 1)))
        phi, jac = np.full(k, np.nan), start.copy()
        phi_of(x, *args, phi)
        jac_of(x, *args, jac)
        fused_phi, fused_jac = np.full(k, np.nan), start.copy()
        both(x, *args, fused_phi, fused_jac)
        assert np.array_equal(phi, fused_phi) and np.array_equal(jac, fused_jac)
        assert not np.array_equal(jac, start)  # the rows were added to
