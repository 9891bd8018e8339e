"""Plate panels (pyfe3d's Tria3DSG shells): frequencies against Leissa's closed forms and
tables, mass and inertia against a uniform plate's.

Closed forms (Leissa, Vibration of Plates, NASA SP-160, 1969): simply supported a x b,
omega_mn = pi^2 (m^2/a^2 + n^2/b^2) sqrt(D / (rho t)), D = E t^3 / (12 (1 - nu^2)); free
square plate, nu = 0.3: omega a^2 sqrt(rho t / D) = 13.468, 19.596, 24.270 (table 4.98).
The element is Mindlin's (shear and rotary inertia, a/t = 100 here: a few 1e-4 below
Kirchhoff's values) and converges from above; errors measured on the meshes below.
Skipped without the optional extra `plate` (pyfe3d).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from mechlib.core.rotation import frame_axes
from mechlib.flexible.beam import Material
from mechlib.flexible.craig_bampton import free_modes
from mechlib.flexible.fe_model import FEModel
from mechlib.flexible.plate import plate

pytest.importorskip("pyfe3d", reason="plate panels need the extra: pip install 'loads[plate]'")

ALUMINIUM = Material(E=70e9, nu=0.3, rho=2700.0)


def _rigidity(t: float) -> float:
    return ALUMINIUM.E * t**3 / (12.0 * (1.0 - ALUMINIUM.nu**2))


def _simply_supported(model: FEModel, a: float, b: float, count: int) -> np.ndarray:
    """The `count` lowest omega (rad/s) of the bending DOF (uz, rx, ry; a flat plate in its
    x-y plane) with uz held on the four edges."""
    xyz, dof = model.coordinates, model.dof_map
    edge = np.isclose(xyz[:, 0], 0.0) | np.isclose(xyz[:, 0], a)
    edge |= np.isclose(xyz[:, 1], 0.0) | np.isclose(xyz[:, 1], b)
    keep = np.isin(dof[:, 1], (2, 3, 4)) & ~((dof[:, 1] == 2) & edge[dof[:, 0]])
    k = model.stiffness[keep][:, keep].tocsc()
    m = model.mass[keep][:, keep].tocsc()
    return np.sqrt(np.sort(spla.eigsh(k, count, m, sigma=0.0, return_eigenvectors=False)))


def test_simply_supported_plate_frequencies():
    """Simply supported 1 x 0.8 x 0.01 m plate, modes (1,1), (2,1), (1,2): within 1 % on
    16 x 16 cells for the fundamental (measured +0.85 %, (2,1) +2.26 %, (1,2) +2.31 %) and
    second-order convergence from 8 x 8 (measured +4.27 %: error ratio 5.0)."""
    a, b, t = 1.0, 0.8, 0.01
    root = np.sqrt(_rigidity(t) / (ALUMINIUM.rho * t))
    exact = np.array(
        [np.pi**2 * (m**2 / a**2 + n**2 / b**2) * root for m, n in ((1, 1), (2, 1), (1, 2))]
    )
    coarse = _simply_supported(plate((a, b), t, ALUMINIUM, (8, 8)).model, a, b, 3) / exact - 1
    fine = _simply_supported(plate((a, b), t, ALUMINIUM, (16, 16)).model, a, b, 3) / exact - 1
    assert 0.0 < fine[0] < 0.01, fine
    assert np.all(fine < [0.0095, 0.025, 0.025]), fine
    assert coarse[0] > 4.0 * fine[0], (coarse, fine)


def test_free_square_plate_through_the_reduction():
    """Free 1 x 1 x 0.01 m plate, 12 x 12 cells, reduced by Craig-Bampton at its centre
    node: the first three elastic frequencies within 1.5 % of Leissa's (measured +0.38 %,
    +0.77 %, +1.23 %); exactly six rigid-body modes (no spurious zero-energy mode)."""
    a, t = 1.0, 0.01
    model = plate((a, a), t, ALUMINIUM, (12, 12), {"centre": (0.5, 0.5)}).model
    omega, _ = free_modes(model, 20)
    factor = omega[:3] * a**2 * np.sqrt(ALUMINIUM.rho * t / _rigidity(t))
    error = factor / np.array([13.468, 19.596, 24.270]) - 1.0
    assert np.all(error > 0.0) and np.all(error < [0.0045, 0.009, 0.014]), error


def test_plate_mass_centre_and_inertia():
    """Consistent mass: exact mass, centre and inertia of the plate (1e-12), the inertia
    about the normal plus the drilling inertia m t^2 / 12 (mechlib.flexible.plate), also
    when the panel is placed and turned."""
    lx, ly, t = 1.2, 0.8, 0.01
    axes = frame_axes((0.0, 0.6, 0.8), (1.0, 0.0, 0.0)).T
    origin = np.array([0.3, -0.2, 1.0])
    placed = plate((lx, ly), t, ALUMINIUM, (6, 4), origin=origin, axes=axes).model
    mass, cm, inertia = placed.rigid_properties()
    m = ALUMINIUM.rho * lx * ly * t
    assert mass == pytest.approx(m, rel=1e-12)
    assert cm == pytest.approx(origin + np.array([lx / 2, ly / 2, 0.0]) @ axes, abs=1e-12)
    local = m / 12.0 * np.diag([ly**2 + t**2, lx**2 + t**2, lx**2 + ly**2 + t**2])
    assert axes @ inertia @ axes.T == pytest.approx(local, abs=1e-12 * m)
    rigid = np.hstack([placed.translation_field(), placed.skew_field(placed.coordinates, True)])
    assert np.abs(placed.stiffness @ rigid).max() < 1e-9 * np.abs(placed.stiffness).max()


def test_interface_points_become_plate_nodes():
    panel = plate((1.0, 0.5), 0.01, ALUMINIUM, (4, 2), {"hinge": (0.0, 0.13), "hold": (0.77, 0.5)})
    xyz = panel.model.coordinates
    assert xyz[panel.nodes["hinge"]] == pytest.approx([0.0, 0.13, 0.0])
    assert xyz[panel.nodes["hold"]] == pytest.approx([0.77, 0.5, 0.0])
    assert set(panel.model.interface) == set(panel.nodes.values())
    with pytest.raises(ValueError, match="outside the panel"):
        plate((1.0, 0.5), 0.01, ALUMINIUM, (4, 2), {"far": (1.5, 0.1)})
