"""Simeon's flexible slider-crank: data, published initial values and reference solution.

Source: the Test Set for IVP Solvers (F. Mazzia, C. Magherini et al., University of Bari),
problem `crank` (index-2 DAE of dimension 24; Fortran source crank.f by B. Simeon, 1998:
subroutines RESMBS, INIT and SOLN), after B. Simeon, "Modelling a flexible slider crank
mechanism by a mixed system of DAEs and PDEs", Math. Modelling of Systems 2 (1996) 1-18.
The default variant: linear stiffness (ipar(1) = 0), no damping (ipar(2) = 0), initial
values "close to smooth motion" (INIT, not INIT2). Nothing here imports the engine.

Coordinates: phi1 (crank angle, rad, = 150 t), phi2 (rod angle, rad), x3 (slider, m),
q1, q2 (amplitudes of sin(pi xi) and sin(2 pi xi), lateral to the chord from the crank pin
to the slider pin, m), q3, q4 (axial displacements of the rod's middle and end relative to
the crank pin, quadratic element, m); xi = x / L2 along the rod.

`equations` is an independent NumPy transcription of RESMBS in index-1 form (the multipliers
eliminated): integrated with scipy's DOP853 at rtol 1e-11 it reproduces SOLN to 3.6e-6
relative (q4; phi2 1.3e-8), the self-check of test_references-style that
test_testset_crank.py runs only with --long (72 s of CPU). Its `axial_mass_factor` measures
one modelling difference: the Test Set's axial mass matrix rho A L [[8, 1], [1, 2]] is 15
times the consistent one of its own quadratic element (rho A L / 15 [[8, 1], [1, 2]]); with
the consistent one q3 and q4 at 0.1 s change by 0.81 % and 0.71 %, phi2 by 2.2e-7.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

NAMES = ("phi1", "phi2", "x3", "q1", "q2", "q3", "q4")
M2, M3 = 0.151104, 0.075552  # kg: rod, slider
L1, L2 = 0.15, 0.30  # m: crank, rod
J1, J2 = 0.002727, 0.0045339259  # kg m^2: crank about its pivot, rod about the crank pin
PI = 3.1415927  # the Test Set's value
EE, BB, HH, RHO = 0.20e12, 0.0080, 0.0080, 7870.0  # Pa, m, m, kg/m^3
OMEGA = 150.0  # rad/s, the crank's prescribed rate

# INIT: positions phi1, phi2, x3, q1..q4 and their rates
Y0 = np.array([0.0, 0.0, 0.450016933, 0.0, 0.0, 0.103339863e-4, 0.169327969e-4])
V0 = np.array(
    [150.0, -74.9957670, -0.268938672e-5, 0.444896105, 0.463434311e-2, -0.178591076e-5,
     -0.268938672e-5]
)  # fmt: skip
# SOLN: at t = 0.1 s
Y_END = np.array(
    [15.0, -3.311734987910881e-01, 1.697373326718410e-01, 1.893192460247178e-04,
     2.375751865617931e-05, -5.323907988763734e-06, -8.363283141616840e-06]
)  # fmt: skip


def shape(xi: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """At xi = x / L2: (axial u, lateral v, slope dv/dx) per unit q1..q4 (4,) each."""
    s1, s2 = np.sin(PI * xi), np.sin(2 * PI * xi)
    c1, c2 = np.cos(PI * xi), np.cos(2 * PI * xi)
    axial = np.array([0.0, 0.0, 4 * xi * (1 - xi), xi * (2 * xi - 1)])
    lateral = np.array([s1, s2, 0.0, 0.0])
    slope = np.array([PI * c1, 2 * PI * c2, 0.0, 0.0]) / L2
    return axial, lateral, slope


def chord_coordinates(a, quarter, middle, three_quarter, b) -> FloatArray:
    """phi2, x3, q1..q4 (6,) from the positions (x, y) of the rod's points at xi = 0, 1/4,
    1/2, 3/4, 1: the chord a -> b is the Test Set's rod axis; the lateral displacements at
    the quarter points give q1, q2 and the third sine (solved out, not reported), the axial
    one at the middle q3, the chord's stretch q4."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    chord = b - a
    length = float(np.hypot(*chord))
    e = chord / length
    n = np.array([-e[1], e[0]])
    v = [float((np.asarray(p, float) - a) @ n) for p in (quarter, middle, three_quarter)]
    s = np.sin(PI / 4)
    q2 = 0.5 * (v[0] - v[2])
    odd = (v[0] + v[2]) / (2 * s)  # q1 + q_third
    q1 = 0.5 * (odd + v[1])  # v(1/2) = q1 - q_third
    q3 = float((np.asarray(middle, float) - a) @ e) - 0.5 * L2
    return np.array([np.arctan2(e[1], e[0]), b[0], q1, q2, q3, length - L2])


def matrices(axial_mass_factor: float = 1.0):
    """MQ, KQ, BQ (4, 4) and c1, c2, c12, c21 (4,) of RESMBS (SI, without rho in c*)."""
    facm, fack, facb = RHO * BB * HH * L2, EE * BB * HH / L2, BB * HH * L2
    mq, kq, bq = np.zeros((4, 4)), np.zeros((4, 4)), np.zeros((4, 4))
    mq[0, 0] = mq[1, 1] = 0.5 * facm
    mq[2:, 2:] = facm * axial_mass_factor * np.array([[8.0, 1.0], [1.0, 2.0]])
    kq[0, 0] = fack * PI**4 / 24 * (HH / L2) ** 2
    kq[1, 1] = fack * PI**4 * 2 / 3 * (HH / L2) ** 2
    kq[2:, 2:] = fack * np.array([[16 / 3, -8 / 3], [-8 / 3, 7 / 3]])
    bq[0, 2], bq[0, 3], bq[1, 3] = -facb * 16 / PI**3, facb * (8 / PI**3 - 1 / PI), facb / (2 * PI)
    bq[2:, :2] = -bq[:2, 2:].T
    c1 = np.array([0.0, 0.0, facb * 2 / 3, facb / 6])
    c2 = np.array([facb * 2 / PI, 0.0, 0.0, 0.0])
    c12 = np.array([0.0, 0.0, L2 * facb / 3, L2 * facb / 6])
    c21 = np.array([L2 * facb / PI, -L2 * facb / (2 * PI), 0.0, 0.0])
    return mq, kq, bq, c1, c2, c12, c21


def equations(axial_mass_factor: float = 1.0):
    """rhs(t, y) of y = [p (7), v (7)]: RESMBS's mass matrix, forces and constraints
    (gravity 0, linear stiffness, no damping), accelerations and multipliers from the
    index-1 saddle-point system."""
    mq, kq, bq, c1, c2, c12, c21 = matrices(axial_mass_factor)

    def rhs(t: float, y: FloatArray) -> FloatArray:
        p1, p2 = y[0], y[1]
        q, v1, v2, qd = y[3:7], y[7], y[8], y[10:14]
        s12, k12 = np.sin(p1 - p2), np.cos(p1 - p2)
        mass = np.zeros((7, 7))
        mass[0, 0] = J1 + M2 * L1 * L1
        mass[0, 1] = 0.5 * L1 * L2 * M2 * k12 + RHO * L1 * (s12 * c2 @ q + k12 * c1 @ q)
        mass[1, 1] = J2 + q @ mq @ q + 2 * RHO * c12 @ q
        mass[2, 2] = M3
        mass[0, 3:] = RHO * L1 * (-s12 * c1 + k12 * c2)
        mass[1, 3:] = RHO * c21 + RHO * (q @ bq)
        mass[3:, 3:] = mq
        mass = np.triu(mass) + np.triu(mass, 1).T
        g = np.zeros((3, 7))
        g[0, :2] = L1 * np.cos(p1), (L2 + q[3]) * np.cos(p2)
        g[1, :3] = L1 * np.sin(p1), (L2 + q[3]) * np.sin(p2), 1.0
        g[0, 6], g[1, 6], g[2, 0] = np.sin(p2), -np.cos(p2), 1.0
        force = np.zeros(7)
        force[0] = (
            -0.5 * L1 * L2 * M2 * v2 * v2 * s12
            + RHO * L1 * v2 * v2 * (-s12 * c1 @ q + k12 * c2 @ q)
            - 2 * RHO * L1 * v2 * (k12 * c1 @ qd + s12 * c2 @ qd)
        )
        force[1] = (
            0.5 * L1 * L2 * M2 * v1 * v1 * s12
            + RHO * L1 * v1 * v1 * (s12 * c1 @ q - k12 * c2 @ q)
            - 2 * RHO * v2 * c12 @ qd
            - 2 * v2 * qd @ mq @ q
            - RHO * qd @ bq @ qd
        )
        force[3:] = (
            v2 * v2 * mq @ q
            + RHO * (v2 * v2 * c12 + L1 * v1 * v1 * (k12 * c1 + s12 * c2) + 2 * v2 * bq @ qd)
            - kq @ q
        )
        curvature = np.array(
            [
                -L1 * np.sin(p1) * v1 * v1
                - (L2 + q[3]) * np.sin(p2) * v2 * v2
                + 2 * v2 * np.cos(p2) * qd[3],
                L1 * np.cos(p1) * v1 * v1
                + (L2 + q[3]) * np.cos(p2) * v2 * v2
                + 2 * v2 * np.sin(p2) * qd[3],
                0.0,
            ]
        )
        saddle = np.block([[mass, g.T], [g, np.zeros((3, 3))]])
        solved = np.linalg.solve(saddle, np.r_[force, -curvature])
        return np.r_[y[7:14], solved[:7]]

    return rhs
