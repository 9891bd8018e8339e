"""Andrews' squeezing mechanism: data, loop closure and the published reference solution.

Source: the Test Set for IVP Solvers (F. Mazzia, C. Magherini et al., problem `andrews`,
release 2.4), after E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II*,
sec. VII.7 (data of Giles 1978 and Manning 1981, equations of Schiehlen 1990). The
reference at t = 0.03 s was computed by the test set's authors with PSIDE at rtol = atol =
1e-14; the consistent initial state (at rest) is theirs. Nothing here imports the engine.

Coordinates (rad): beta (crank k1, absolute), Theta (k2 relative to k1), gamma (k3,
absolute), Phi (k4 relative to k5), delta (k5, absolute), Omega (k6 relative to k7),
epsilon (k7, absolute). All values SI.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

NAMES = ("beta", "Theta", "gamma", "Phi", "delta", "Omega", "epsilon")
JOINTS = ("o", "f", "b", "g", "a5", "h", "a7")
"""The case file's joint of each coordinate (the same order as NAMES)."""

# Geometry (m), Hairer & Wanner table 7.1
XA, YA = -0.06934, -0.00227
XB, YB = -0.03635, 0.03273
XC, YC = 0.014, 0.072
D, DA, E, EA = 0.028, 0.0115, 0.02, 0.01421
RR, RA = 0.007, 0.00092
SS, SA, SB, SC, SD = 0.035, 0.01874, 0.01043, 0.018, 0.02
TA, TB = 0.02308, 0.00916
U, UA, UB = 0.04, 0.01228, 0.00449
ZF, ZT, FA = 0.02, 0.04, 0.01421
MASSES = (0.04325, 0.00365, 0.02373, 0.00706, 0.07050, 0.00706, 0.05498)  # kg, k1..k7
IZZ = (2.194e-6, 4.410e-7, 5.255e-6, 5.667e-7, 1.169e-5, 5.667e-7, 1.912e-5)  # kg*m^2, about cm
TORQUE = 0.033  # N*m on k1
SPRING_STIFFNESS, SPRING_FREE_LENGTH = 4530.0, 0.07785  # N/m, m (D on k3 to the fixed C)

Q0 = np.array(
    [
        -0.0617138900142764496358948458001,
        0.0,
        0.455279819163070380255912382449,
        0.222668390165885884674473185609,
        0.487364979543842550225598953530,
        -0.222668390165885884674473185609,
        1.23054744454982119249735015568,
    ]
)
"""Consistent initial coordinates (rad); the velocities are zero."""
LAMBDA0 = np.array([98.5668703962410896057654982170, -6.12268834425566265503114393122])
"""Initial multipliers of the constraint E(k2) = E(k3): the force (N) on k3 from k2 at E."""

END = 0.03  # s
Q_END = np.array(
    [
        15.81077119629904,
        -15.75637105984298,
        0.04082224013073101,
        -0.5347301163226948,
        0.5244099658805304,
        0.5347301163226948,
        1.048080741042263,
    ]
)
"""Coordinates at t = 0.03 s (rad), the test set's reference."""
V_END = np.array(
    [
        1139.920302151208,
        -1424.379294994111,
        11.03291221937134,
        19.29337464421385,
        0.5735699284790808,
        -19.29337464421385,
        0.3231791658026955,
    ]
)
"""Rates at t = 0.03 s (rad/s)."""
LAMBDA_END = np.array([199.1753333731910, -29.75531228015052])
"""Multipliers of E(k2) = E(k3) at t = 0.03 s: the force (N) on k3 from k2 at E."""


def _along(angle: float) -> FloatArray:
    return np.array([np.cos(angle), np.sin(angle)])


def _across(angle: float) -> FloatArray:
    """Unit vector (sin a, -cos a): the test set's second direction of each body."""
    return np.array([np.sin(angle), -np.cos(angle)])


def loop_points(q: FloatArray) -> dict[str, FloatArray]:
    """Planar positions (m) of the joint points, spring ends and centres of mass at `q`.

    E is reached four ways (from k2, k3, k4 and k6): `E2`, `E3`, `E4`, `E6`, equal where the
    loop constraints hold. The centres of mass of k3, k5 and k7 sit at (sa, sb), (ta, tb),
    (ua, ub) along / across their bodies: the test set fixes only their distance from the
    pivot (our choice of direction, as in the case file)."""
    beta, theta, gamma, phi, delta, omega, eps = q
    a, b = np.array([XA, YA]), np.array([XB, YB])
    f = RR * _along(beta)
    g = a + ZT * _along(delta)
    h = a + U * _across(eps)
    return {
        "O": np.zeros(2),
        "F": f,
        "E2": f - D * _along(beta + theta),
        "B": b,
        "E3": b + SS * _across(gamma),
        "D": b + SD * _along(gamma) + SC * _across(gamma),
        "C": np.array([XC, YC]),
        "A": a,
        "G": g,
        "E4": g + E * _across(phi + delta),
        "H": h,
        "E6": h + ZF * _along(omega + eps),
        "cm1": RA * _along(beta),
        "cm2": f - DA * _along(beta + theta),
        "cm3": b + SA * _across(gamma) + SB * _along(gamma),
        "cm4": g + (E - EA) * _across(phi + delta),
        "cm5": a + TA * _along(delta) + TB * _across(delta + np.pi),
        "cm6": h + (ZF - FA) * _along(omega + eps),
        "cm7": a + UA * _across(eps) + UB * _along(eps),
    }


def loop_residual(q: FloatArray) -> float:
    """Largest gap (m) between the four positions of E at `q`: the test set's 6 constraints."""
    p = loop_points(q)
    return max(float(np.max(np.abs(p[k] - p["E2"]))) for k in ("E3", "E4", "E6"))
