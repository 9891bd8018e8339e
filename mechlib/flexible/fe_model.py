"""A linear finite element model of one flexible component, as the reduction reads it.

Every source of stiffness and mass (the built-in beam and grillage, imported neutral files,
Matrix Market, NASTRAN OP4/DMIG) produces an ``FEModel``; the Craig-Bampton reduction takes
one. Units are SI throughout (m, kg, s, N, rad); readers convert before building it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["COMPONENTS", "FEModel"]

COMPONENTS = ("ux", "uy", "uz", "rx", "ry", "rz")  # nodal DOF components, in this order


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
