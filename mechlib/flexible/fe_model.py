"""A linear finite element model of one flexible component, as the reduction reads it.

Every source of stiffness and mass (the built-in beam and grillage, imported neutral files,
Matrix Market, NASTRAN OP4/DMIG) produces an ``FEModel``; the Craig-Bampton reduction takes
one. Units are SI throughout (m, kg, s, N, rad); readers convert before building it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["COMPONENTS", "BeamSet", "FEModel"]

COMPONENTS = ("ux", "uy", "uz", "rx", "ry", "rz")  # nodal DOF components, in this order


@dataclass(frozen=True)
class BeamSet:
    """The beam elements of a built-in model, for the geometric stiffness
    (mechlib.flexible.stiffening): end node indices `a`, `b` (e,), axial stiffness `EA`
    (e,) N, lengths `length` (e,) m, local axes `axes` (e, 3, 3) rows x (along), y, z."""

    a: np.ndarray
    b: np.ndarray
    EA: np.ndarray
    length: np.ndarray
    axes: np.ndarray


@dataclass(frozen=True)
class FEModel:
    """Stiffness and mass of a component in its own frame (SI units).

    ``dof_map[i] = (node index, component)`` names the model's i-th DOF, component 0-5 as in
    ``COMPONENTS``; a node may carry only some components (solids: translations only; DOF
    already constrained are absent). ``interface`` lists node indices where the mechanism
    attaches (joints, springs, contacts, loads, requests); they must carry all six DOF.
    """

    node_ids: np.ndarray  # (n,) int: the user's node numbers
    coordinates: np.ndarray  # (n, 3) m: undeformed node positions in the component frame
    dof_map: np.ndarray  # (ndof, 2) int: node index, component 0-5
    stiffness: sp.csr_matrix  # (ndof, ndof) N/m, N/rad, N*m/rad
    mass: sp.csr_matrix  # (ndof, ndof) kg, kg*m, kg*m^2
    interface: tuple[int, ...]  # node indices (into node_ids)
    beams: BeamSet | None = None  # the elements of a built-in beam or grillage, else None

    def __post_init__(self) -> None:
        n = len(self.node_ids)
        ndof = len(self.dof_map)
        if self.coordinates.shape != (n, 3):
            raise ValueError(f"coordinates must be ({n}, 3), got {self.coordinates.shape}")
        if self.stiffness.shape != (ndof, ndof) or self.mass.shape != (ndof, ndof):
            raise ValueError(f"stiffness and mass must be ({ndof}, {ndof}) like the DOF map")
        for node in self.interface:
            if int(np.count_nonzero(self.dof_map[:, 0] == node)) != 6:
                raise ValueError(f"interface node {self.node_ids[node]} must carry all six DOF")

    def dof_index(self, node: int, component: int) -> int:
        """Row of ``(node index, component)`` in the matrices; KeyError if absent."""
        hits = np.flatnonzero((self.dof_map[:, 0] == node) & (self.dof_map[:, 1] == component))
        if hits.size == 0:
            raise KeyError(f"node {self.node_ids[node]} has no DOF {COMPONENTS[component]}")
        return int(hits[0])

    def skew_field(self, vectors: np.ndarray, rotations: bool) -> np.ndarray:
        """(ndof, 3) field: translation rows -skew(v_p) of one vector per node (n, 3),
        rotation rows I when `rotations` else 0. With v = positions it is the motion of a
        small rotation (R0 of the flexible-body notes); with v = a mode's translations it is
        R_j."""
        nodes, comps = self.dof_map[:, 0], self.dof_map[:, 1]
        out = np.zeros((len(self.dof_map), 3))
        v = vectors[nodes]
        trans = comps < 3
        # rows of -skew(v): (0, v2, -v1), (-v2, 0, v0), (v1, -v0, 0)
        for c, (a, sa, b, sb) in enumerate(
            ((2, 1.0, 1, -1.0), (0, 1.0, 2, -1.0), (1, 1.0, 0, -1.0))
        ):
            rows = trans & (comps == c)
            out[rows, (c + 1) % 3] = sa * v[rows, a]
            out[rows, (c + 2) % 3] = sb * v[rows, b]
        if rotations:
            rot = ~trans
            out[rot, comps[rot] - 3] = 1.0
        return out

    def translation_field(self) -> np.ndarray:
        """(ndof, 3) Gamma: a unit translation along each axis."""
        out = np.zeros((len(self.dof_map), 3))
        trans = self.dof_map[:, 1] < 3
        out[trans, self.dof_map[trans, 1]] = 1.0
        return out

    def rigid_properties(self) -> tuple[float, np.ndarray, np.ndarray]:
        """(mass kg, centre of mass (3,) m, inertia (3, 3) kg*m^2 about it), from the mass
        matrix and rigid motions (exact for lumped and consistent mass alike)."""
        gamma = self.translation_field()
        mg = self.mass @ gamma
        mass = float(gamma[:, 0] @ mg[:, 0])
        r0 = self.skew_field(self.coordinates, True)
        moment = gamma.T @ (self.mass @ r0)  # = -m skew(c)
        cm = np.array([moment[1, 2], moment[2, 0], moment[0, 1]]) / mass
        rc = self.skew_field(self.coordinates - cm, True)
        return mass, cm, rc.T @ (self.mass @ rc)
