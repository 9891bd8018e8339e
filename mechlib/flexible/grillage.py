"""A flat panel as a grillage of Timoshenko beams, from a few numbers (SI).

The panel lies in its own x-y plane, corner at the origin, thickness along z. Grid lines run
along x and y; each line is a beam strip of solid rectangular section (tributary width x
thickness). Each direction carries half the density, so that the grillage's mass is the
panel's, rho lx ly t, exactly; bending stiffness per unit width is E t^3/12 in each
direction (a grillage ignores the plate's Poisson coupling, 1 - nu^2 = 0.91 for nu = 0.3,
and its twisting stiffness is the strips' torsion: an approximation of a plate). Interface
points (hinges, hold-downs) become grid nodes: the grid lines pass through them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mechlib.flexible.beam import Material, Section, assemble_beams
from mechlib.flexible.fe_model import FEModel

__all__ = ["NamedModel", "PanelGrid", "grillage", "panel_grid", "straight_beam"]

_MERGE = 1e-9  # relative to the panel size: grid lines closer than this are one line


@dataclass(frozen=True)
class NamedModel:
    """An FEModel and its named interface nodes (name -> node index)."""

    model: FEModel
    nodes: dict[str, int] = field(default_factory=dict)


def _lines(length: float, count: int, extra) -> np.ndarray:
    """Grid coordinates 0..length (m): `count` equal cells plus the lines through `extra`."""
    values = np.sort(np.r_[np.linspace(0.0, length, count + 1), np.asarray(extra, float)])
    keep = np.r_[True, np.diff(values) > _MERGE * length]
    return values[keep]


def _tributary(lines: np.ndarray) -> np.ndarray:
    """Width (m) each grid line stands for: half the cells on either side."""
    cells = np.diff(lines)
    return 0.5 * (np.r_[cells, 0.0] + np.r_[0.0, cells])


@dataclass(frozen=True)
class PanelGrid:
    """The nodes of a flat panel's grid: lines `xs` (nx,) and `ys` (ny,) m in the panel
    frame, node i * ny + j at (xs[i], ys[j]); `xyz` (n, 3) m placed; `axes` (3, 3) rows the
    panel's x, y, z (normal) axes; `nodes` the named interface points' node indices."""

    xs: np.ndarray
    ys: np.ndarray
    xyz: np.ndarray
    axes: np.ndarray
    nodes: dict[str, int]

    def node(self, i: int, j: int) -> int:
        """Index of the node at (xs[i], ys[j])."""
        return i * len(self.ys) + j

    def tributary_area(self) -> np.ndarray:
        """(n,) m^2: the area each node stands for (half the cells on either side)."""
        return np.outer(_tributary(self.xs), _tributary(self.ys)).ravel()


def panel_grid(
    size: tuple[float, float],
    mesh: tuple[int, int],
    interface: dict[str, tuple[float, float]] | None = None,
    *,
    origin=(0.0, 0.0, 0.0),
    axes=None,
) -> PanelGrid:
    """The grid of a panel `size` = (lx, ly) m in `mesh` = (nx, ny) cells, grid lines also
    through the named interface points (x, y) m (panel frame); the corner placed at `origin`
    (m) with `axes` (rows: the panel's x, y, z axes; default the model's axes). ValueError
    for a point outside the panel."""
    lx, ly = size
    interface = interface or {}
    for name, (x, y) in interface.items():
        if not (-_MERGE <= x / lx <= 1 + _MERGE and -_MERGE <= y / ly <= 1 + _MERGE):
            raise ValueError(f"interface point {name} ({x}, {y}) m is outside the panel")
    xs = _lines(lx, mesh[0], [p[0] for p in interface.values()])
    ys = _lines(ly, mesh[1], [p[1] for p in interface.values()])
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    local = np.column_stack([gx.ravel(), gy.ravel(), np.zeros(gx.size)])
    rot = np.eye(3) if axes is None else np.asarray(axes, dtype=float)
    nodes = {
        name: int(np.argmin(np.hypot(local[:, 0] - x, local[:, 1] - y)))
        for name, (x, y) in interface.items()
    }
    return PanelGrid(xs, ys, np.asarray(origin, dtype=float) + local @ rot, rot, nodes)


def grillage(
    size: tuple[float, float],
    thickness: float,
    material: Material,
    mesh: tuple[int, int],
    interface: dict[str, tuple[float, float]] | None = None,
    *,
    origin=(0.0, 0.0, 0.0),
    axes=None,
) -> NamedModel:
    """A panel `size` = (lx, ly) m, `thickness` m, `mesh` = (nx, ny) cells, with interface
    nodes at the named (x, y) positions (m, panel frame); the panel frame's corner placed at
    `origin` (m) with `axes` (rows: its x, y, z axes; default the model's axes)."""
    grid = panel_grid(size, mesh, interface, origin=origin, axes=axes)
    rot, nx, ny = grid.axes, len(grid.xs), len(grid.ys)
    half = Material(material.E, material.nu, 0.5 * material.rho)
    elements = []
    for j, width in enumerate(_tributary(grid.ys)):  # strips along x
        section = Section.rectangle(width, thickness)
        elements += [
            (grid.node(i, j), grid.node(i + 1, j), section, half, rot[1]) for i in range(nx - 1)
        ]
    for i, width in enumerate(_tributary(grid.xs)):  # strips along y: local y = -x, z = normal
        section = Section.rectangle(width, thickness)
        elements += [
            (grid.node(i, j), grid.node(i, j + 1), section, half, -rot[0]) for j in range(ny - 1)
        ]
    interface_nodes = tuple(dict.fromkeys(grid.nodes.values()))
    return NamedModel(assemble_beams(grid.xyz, elements, interface=interface_nodes), grid.nodes)


def straight_beam(
    start,
    end,
    section: Section,
    material: Material,
    elements: int,
    interface: dict[str, tuple[float, float, float]] | None = None,
    y_axis=(0.0, 0.0, 1.0),
) -> NamedModel:
    """A straight beam from `start` to `end` (m) in `elements` equal elements plus nodes at
    the named interface points (m, on the beam's line); section y axis near `y_axis`."""
    a, b = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    length = float(np.linalg.norm(b - a))
    axis = (b - a) / length
    interface = interface or {}
    along = {}
    for name, point in interface.items():
        d = np.asarray(point, dtype=float) - a
        s = float(d @ axis)
        if np.linalg.norm(d - s * axis) > _MERGE * length + 1e-9 or not (
            -_MERGE <= s / length <= 1 + _MERGE
        ):
            raise ValueError(f"interface point {name} is not on the beam from start to end")
        along[name] = s
    stations = _lines(length, elements, list(along.values()))
    xyz = a + np.outer(stations, axis)
    beams = [(i, i + 1, section, material, np.asarray(y_axis, float)) for i in range(len(xyz) - 1)]
    nodes = {name: int(np.argmin(np.abs(stations - s))) for name, s in along.items()}
    return NamedModel(
        assemble_beams(xyz, beams, interface=tuple(dict.fromkeys(nodes.values()))), nodes
    )
