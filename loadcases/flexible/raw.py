"""What every format reader hands over before units, checks and the interface: matrices in
the file's units with their DOF map by node id, and the nodes."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import scipy.sparse as sp

__all__ = ["RawModel"]


@dataclass
class RawModel:
    """Matrices and nodes as read (file units). `dofs[i]` = (node id, component 1-6) of row
    i; `interface` the node ids the files themselves name (NASTRAN ASET grids) when the
    header names none; `wtmass` PARAM,WTMASS found in the files (value, file, line)."""

    stiffness: sp.csr_matrix
    mass: sp.csr_matrix
    dofs: np.ndarray
    node_ids: np.ndarray
    coordinates: np.ndarray
    stiffness_file: Path
    mass_file: Path
    node_names: dict[str, int] = field(default_factory=dict)  # name -> node id
    interface: list[int] = field(default_factory=list)
    wtmass: tuple[float, str, int] | None = None
    files: list[Path] = field(default_factory=list)  # every file read, header excepted
