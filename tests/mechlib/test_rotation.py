"""Euler-parameter kinematics of mechlib.core.rotation against scipy and finite differences.

References: scipy.spatial.transform.Rotation (independent implementation of the
quaternion -> matrix map, scalar-first convention); the definitions A(p) s (rotation of a
body-fixed vector), B(p, s) = d(A s)/dp and skew(omega) = Adot A^T (Haug 1989, ch. 9;
Nikravesh 1988, ch. 6).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mechlib.core.rotation import (
    d_rotate,
    e_matrix,
    g_matrix,
    omega_global,
    quaternion_from_rotvec,
    rotate,
    rotation_matrix,
    skew,
)

N_SAMPLES = 20


@pytest.fixture()
def rng() -> np.random.Generator:
    """A seeded generator: the random samples are the same on every run."""
    return np.random.default_rng(20261121)


def _unit_quaternions(rng: np.random.Generator, n: int = N_SAMPLES) -> np.ndarray:
    p = rng.normal(size=(n, 4))
    return p / np.linalg.norm(p, axis=1, keepdims=True)


def test_rotation_matrix_matches_scipy(rng: np.random.Generator) -> None:
    """A(p) equals scipy's matrix of the same scalar-first unit quaternion to 1e-14
    (round-off of a quadratic form of unit-size entries)."""
    p = _unit_quaternions(rng)
    expected = Rotation.from_quat(p, scalar_first=True).as_matrix()
    assert np.abs(rotation_matrix(p) - expected).max() < 1e-14


def test_rotation_matrix_is_orthonormal_and_proper(rng: np.random.Generator) -> None:
    """A A^T = I and det A = +1 on the unit sphere (1e-14, round-off)."""
    a = rotation_matrix(_unit_quaternions(rng))
    assert np.abs(a @ np.swapaxes(a, -1, -2) - np.eye(3)).max() < 1e-14
    assert np.abs(np.linalg.det(a) - 1.0).max() < 1e-14


def test_rotate_equals_matrix_times_vector(rng: np.random.Generator) -> None:
    """rotate(p, s) = A(p) s, also off the unit sphere where both scale with |p|^2
    (the homogeneous form the module documents); 1e-13 round-off."""
    p = rng.normal(size=(N_SAMPLES, 4))
    s = rng.normal(size=(N_SAMPLES, 3))
    expected = np.einsum("nij,nj->ni", rotation_matrix(p), s)
    assert np.abs(rotate(p, s) - expected).max() < 1e-13


def test_quaternion_from_rotvec_matches_scipy(rng: np.random.Generator) -> None:
    """The quaternion of a rotation vector gives scipy's rotation matrix (1e-14)."""
    for v in rng.normal(size=(N_SAMPLES, 3)):
        expected = Rotation.from_rotvec(v).as_matrix()
        assert np.abs(rotation_matrix(quaternion_from_rotvec(v)) - expected).max() < 1e-14


def test_d_rotate_matches_central_differences(rng: np.random.Generator) -> None:
    """B(p, s) = d(A(p) s)/dp by central differences with step 1e-6. A(p) s is quadratic
    in p, so central differences are exact up to round-off (~1e-16 / 1e-6 = 1e-10)."""
    p = rng.normal(size=(N_SAMPLES, 4))
    s = rng.normal(size=(N_SAMPLES, 3))
    step = 1e-6
    fd = np.empty((N_SAMPLES, 3, 4))
    for j in range(4):
        dp = np.zeros(4)
        dp[j] = step
        fd[:, :, j] = (rotate(p + dp, s) - rotate(p - dp, s)) / (2.0 * step)
    assert np.abs(d_rotate(p, s) - fd).max() < 1e-8


def test_d_rotate_polarisation_identity(rng: np.random.Generator) -> None:
    """B(pd, s) pd = 2 A(pd) s (the identity the gamma kernels rely on), 1e-13."""
    pd = rng.normal(size=(N_SAMPLES, 4))
    s = rng.normal(size=(N_SAMPLES, 3))
    lhs = np.einsum("nij,nj->ni", d_rotate(pd, s), pd)
    assert np.abs(lhs - 2.0 * rotate(pd, s)).max() < 1e-13


def test_omega_global_is_the_rate_of_the_rotation_matrix(rng: np.random.Generator) -> None:
    """skew(omega) = Adot A^T with Adot by central differences along p + t pd (p.pd = 0,
    the unit-norm condition). A is quadratic in t: central differences exact but for
    round-off (step 1e-6 -> ~1e-10)."""
    step = 1e-6
    for p in _unit_quaternions(rng):
        pd = rng.normal(size=4)
        pd -= (pd @ p) * p
        a_dot = (rotation_matrix(p + step * pd) - rotation_matrix(p - step * pd)) / (2 * step)
        expected = a_dot @ rotation_matrix(p).T
        assert np.abs(skew(omega_global(p, pd)) - expected).max() < 1e-8


def test_body_and_global_angular_velocity_are_related_by_a(rng: np.random.Generator) -> None:
    """omega' = 2 G pd (body axes) equals A^T omega, omega = 2 E pd (1e-13)."""
    for p in _unit_quaternions(rng):
        pd = rng.normal(size=4)
        pd -= (pd @ p) * p
        omega_body = 2.0 * g_matrix(p) @ pd
        assert np.abs(omega_body - rotation_matrix(p).T @ (2.0 * e_matrix(p) @ pd)).max() < 1e-13


def test_e_matrix_is_a_right_inverse_pair(rng: np.random.Generator) -> None:
    """E E^T = I and E p = 0 on the unit sphere, so n = E Q_p / 2 recovers a torque from its
    generalised force Q_p = 2 E^T n (used by the reaction requests); 1e-14."""
    for p in _unit_quaternions(rng):
        e = e_matrix(p)
        assert np.abs(e @ e.T - np.eye(3)).max() < 1e-14
        assert np.abs(e @ p).max() < 1e-14
