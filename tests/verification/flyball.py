"""IFToMM benchmark A05, the stiff flyball governor: data and an independent reference.

Source of the model: the IFToMM library of computational benchmark problems, A05 (M.
Gonzalez, D. Dopico, U. Lugris, J. Cuadrado, Multibody Syst. Dyn. 16 (2006) 179-190), as
restated by the OpenSim implementation of the library (RehabEngGroup/MBSbenchmarksInOpenSim,
src/A05-FlyballGovernor). No published time history of the benchmark could be obtained, so
the reference is computed here, independently of the engine: Lagrange's equations in the
minimal coordinates (psi the shaft's spin angle, theta each rod's angle from the downward
vertical, the two arms moving alike, z the slider's height), derived by hand below and
solved by scipy's LSODA at rtol 1e-11 (within 1e-10 of each quantity's peak of scipy's
Radau at rtol 1e-12 over 0.6 s, 16 times faster). Nothing here imports the engine. All values SI.

    T = J(theta) psi'^2 / 2 + ARM theta'^2 + MS z'^2 / 2
    J = I_shaft + I_slider + 2 [MB (A + L s)^2 + MR (A + s / 2)^2 + IT s^2 + IA c^2]
    V = g [MS z + 2 MB (H - L c) + 2 MR (H - c / 2)] + k (d - D0)^2   (two springs)
    d^2 = (s / 2)^2 + (H - c / 2 - z)^2,  s = sin theta, c = cos theta

with the damper force c d' along each spring; J psi' (the angular momentum about the
shaft) is conserved, T + V falls by 2 c d'^2 per second.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import solve_ivp

FloatArray = NDArray[np.float64]

G = 9.81  # m/s^2, along -z (the shaft)
MS, MR, MB = 3.0, 0.3, 5.0  # kg: slider (0.1 m cube), shaft and rods (1 x 0.01 x 0.01 m), balls
L, A, H = 1.0, 0.05, 1.0  # m: rod length (ball at its end), hinge offset, hinge height
STIFFNESS, DAMPING, D0 = 8.0e5, 4.0e4, 0.5  # N/m, N*s/m, m (free length)
IA, IT = MR * 2e-4 / 12, MR * (1 + 1e-4) / 12  # kg*m^2: a rod along and across its axis
I_SPIN = MR * 2e-4 / 12 + MS * 0.02 / 12  # kg*m^2: shaft and slider about the shaft
ARM = MB * L**2 + MR * L**2 / 4 + IT  # kg*m^2: an arm about its hinge
THETA0, Z0, SPIN0 = np.pi / 3, 0.5, 2 * np.pi  # rad, m, rad/s: the start


def spin_inertia(theta: FloatArray) -> FloatArray:
    """J(theta): moment of inertia of the whole governor about the shaft (kg*m^2)."""
    s, c = np.sin(theta), np.cos(theta)
    arm = MB * (A + L * s) ** 2 + MR * (A + 0.5 * s) ** 2 + IT * s * s + IA * c * c
    return I_SPIN + 2 * arm


def _spin_inertia_slope(theta: float) -> float:
    """dJ/dtheta (kg*m^2/rad)."""
    s, c = np.sin(theta), np.cos(theta)
    return 2 * (2 * MB * (A + L * s) * L * c + MR * (A + 0.5 * s) * c + 2 * (IT - IA) * s * c)


def spring_length(theta, z):
    """(d, dd/dtheta, dd/dz): a spring's length (m) and its slopes."""
    dz = H - 0.5 * np.cos(theta) - z
    d = np.hypot(0.5 * np.sin(theta), dz)
    return d, (0.25 * np.sin(theta) * np.cos(theta) + 0.5 * dz * np.sin(theta)) / d, -dz / d


def spring_tension(y: FloatArray) -> FloatArray:
    """k (d - D0) + c d' (N) of each spring along the solution rows y (5, n)."""
    theta, z, _, theta_rate, z_rate = y
    d, d_theta, d_z = spring_length(theta, z)
    return STIFFNESS * (d - D0) + DAMPING * (d_theta * theta_rate + d_z * z_rate)


def _rhs(t: float, y: FloatArray) -> list[float]:
    """y = (theta, z, psi', theta', z') (psi itself is cyclic: not needed): Lagrange's
    equations solved for the rates."""
    theta, z, spin, theta_rate, z_rate = y
    d, d_theta, d_z = spring_length(theta, z)
    tension = STIFFNESS * (d - D0) + DAMPING * (d_theta * theta_rate + d_z * z_rate)
    slope = _spin_inertia_slope(theta)
    weight = G * (2 * MB * L + MR) * np.sin(theta)  # dV_gravity/dtheta
    theta_acc = (0.5 * slope * spin**2 - weight - 2 * tension * d_theta) / (2 * ARM)
    z_acc = (-G * MS - 2 * tension * d_z) / MS
    spin_acc = -slope * theta_rate * spin / spin_inertia(theta)
    return [theta_rate, z_rate, spin_acc, theta_acc, z_acc]


def flyball_solve(times: FloatArray) -> FloatArray:
    """The reference at `times` (s, from 0): rows theta, z, psi', theta', z' (5, n)."""
    start = [THETA0, Z0, SPIN0, 0.0, 0.0]
    sol = solve_ivp(
        _rhs, (0.0, float(times[-1])), start, method="LSODA", rtol=1e-11, atol=1e-13, t_eval=times
    )
    assert sol.status == 0, sol.message
    return sol.y


def flyball_energy(y: FloatArray) -> FloatArray:
    """T + V (J) along the solution rows y (5, n); the datum of gravity is z = 0."""
    theta, z, spin, theta_rate, z_rate = y
    kinetic = 0.5 * spin_inertia(theta) * spin**2 + ARM * theta_rate**2 + 0.5 * MS * z_rate**2
    c = np.cos(theta)
    gravity = G * (MS * z + 2 * MB * (H - L * c) + 2 * MR * (H - 0.5 * c))
    d = spring_length(theta, z)[0]
    return kinetic + gravity + STIFFNESS * (d - D0) ** 2
