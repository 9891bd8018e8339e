"""A flat panel as Mindlin plate/shell elements (pyfe3d's Tria3DSG), from a few numbers (SI).

The optional extra `plate` (``pip install 'loads[plate]'``, pyfe3d) gives the element; it is
imported only when a plate is built. The panel's grid and placement are the grillage's
(mechlib.flexible.grillage.panel_grid): interface points become grid nodes. Each cell is
two Tria3DSG shells split along its (i, j)-(i+1, j+1) diagonal (membrane, bending with
Poisson coupling and twisting stiffness, transverse shear by discrete shear gaps with 5/6,
the drilling rotation tied to the membrane's rotation), 6 DOF per node in the model's
axes, consistent mass (exact mass and rigid-body inertia). pyfe3d's Quad4 is not used:
its one-point shear leaves an hourglass mode w = (-1)^(i+j) of zero energy in a free
panel, which a Craig-Bampton reduction held at points cannot remove.

pyfe3d gives the drilling rotation no inertia; a massless DOF would make the mass matrix
singular (the fixed-interface eigenproblem needs it positive definite), so each node gets
the rotary inertia rho t^3/12 of its tributary area about the panel's normal: it adds
m t^2/12 to the inertia about the normal (a share t^2 / (lx^2 + ly^2) of it) and touches
only the membrane modes (a flat plate's bending does not couple to the drilling rotation).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from mechlib.flexible.beam import Material
from mechlib.flexible.fe_model import FEModel
from mechlib.flexible.grillage import NamedModel, PanelGrid, panel_grid

__all__ = ["plate", "plate_matrices"]


def _triangles(grid: PanelGrid) -> list[tuple[int, int, int]]:
    """Node triples of the triangles (two per cell), counter-clockwise about the normal."""
    out = []
    for i in range(len(grid.xs) - 1):
        for j in range(len(grid.ys) - 1):
            a, b = grid.node(i, j), grid.node(i + 1, j + 1)
            out += [(a, grid.node(i + 1, j), b), (a, b, grid.node(i, j + 1))]
    return out


def plate_matrices(
    grid: PanelGrid, thickness: float, material: Material
) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Stiffness (N/m, N/rad, N*m/rad) and consistent mass (kg, kg*m, kg*m^2) of the
    panel's shells, 6 DOF per node (ux uy uz rx ry rz, model axes); the drilling
    inertia of the module's note included. ImportError when pyfe3d is not installed."""
    import pyfe3d
    from pyfe3d.shellprop_utils import isotropic_plate

    prop = isotropic_plate(thickness, material.E, material.nu, rho=material.rho)
    triangles = _triangles(grid)
    data, probe = pyfe3d.Tria3DSGData(), pyfe3d.Tria3DSGProbe()
    nk, nm = len(triangles) * data.KC0_SPARSE_SIZE, len(triangles) * data.M_SPARSE_SIZE
    kr, kc, kv = np.zeros(nk, pyfe3d.INT), np.zeros(nk, pyfe3d.INT), np.zeros(nk)
    mr, mc, mv = np.zeros(nm, pyfe3d.INT), np.zeros(nm, pyfe3d.INT), np.zeros(nm)
    x = np.ascontiguousarray(grid.xyz.ravel())
    for e, (n1, n2, n3) in enumerate(triangles):
        tria = pyfe3d.Tria3DSG(probe)
        tria.n1, tria.n2, tria.n3 = n1, n2, n3
        tria.c1, tria.c2, tria.c3 = 6 * n1, 6 * n2, 6 * n3
        tria.init_k_KC0 = e * data.KC0_SPARSE_SIZE
        tria.init_k_M = e * data.M_SPARSE_SIZE
        tria.update_rotation_matrix(x)
        tria.update_probe_xe(x)
        tria.update_KC0(kr, kc, kv, prop)
        tria.update_M(mr, mc, mv, prop, mtype=0)
    ndof = 6 * len(grid.xyz)
    stiffness = sp.coo_matrix((kv, (kr, kc)), shape=(ndof, ndof)).tocsr()
    mass = sp.coo_matrix((mv, (mr, mc)), shape=(ndof, ndof)).tocsr()
    return stiffness, (mass + _drilling_inertia(grid, prop.intrhoz2)).tocsr()


def _drilling_inertia(grid: PanelGrid, per_area: float) -> sp.csr_matrix:
    """Rotary inertia `per_area` (kg*m^2/m^2) x tributary area about the normal, per node."""
    normal = grid.axes[2]
    block = np.outer(normal, normal)
    blocks = [
        sp.block_diag((np.zeros((3, 3)), j * block)) for j in per_area * grid.tributary_area()
    ]
    return sp.block_diag(blocks, format="csr")


def plate(
    size: tuple[float, float],
    thickness: float,
    material: Material,
    mesh: tuple[int, int],
    interface: dict[str, tuple[float, float]] | None = None,
    *,
    origin=(0.0, 0.0, 0.0),
    axes=None,
) -> NamedModel:
    """A plate panel `size` = (lx, ly) m, `thickness` m, `mesh` = (nx, ny) cells, with
    interface nodes at the named (x, y) positions (m, panel frame); the corner placed at
    `origin` (m) with `axes` (rows: the panel's x, y, z axes); as grillage() but of plate
    elements. ImportError when pyfe3d is not installed, ValueError for a point outside."""
    grid = panel_grid(size, mesh, interface, origin=origin, axes=axes)
    stiffness, mass = plate_matrices(grid, thickness, material)
    n = len(grid.xyz)
    dof_map = np.column_stack([np.repeat(np.arange(n), 6), np.tile(np.arange(6), n)])
    model = FEModel(
        np.arange(1, n + 1),
        grid.xyz,
        dof_map,
        stiffness,
        mass,
        tuple(dict.fromkeys(grid.nodes.values())),
    )
    return NamedModel(model, grid.nodes)
