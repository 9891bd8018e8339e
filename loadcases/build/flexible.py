"""Flexible bodies of a mechanism file -> modal components (mechlib.flexible), issue 13.

Each `interface:` point becomes a node of the FE model (and a point `BODY.NAME` of the
mechanism: loadcases.schema.mechanism); the Craig-Bampton reduction keeps those nodes.
"""

from __future__ import annotations

import numpy as np

from loadcases.schema.flexible import BeamSection, Flexible, MaterialModel
from mechlib.flexible.beam import Material, Section
from mechlib.flexible.craig_bampton import craig_bampton
from mechlib.flexible.grillage import NamedModel, grillage, straight_beam
from mechlib.flexible.modal_component import ModalComponent

__all__ = ["flexible_component"]

_IN_PLANE = 1e-6  # m: interface points farther than this from the panel's plane are errors


def _material(m: MaterialModel) -> Material:
    return Material(m.E, m.nu, m.rho)


def _section(s: BeamSection) -> Section:
    if s.width is not None and s.height is not None:
        return Section.rectangle(s.width, s.height, shear=s.shear)
    k = 5.0 / 6.0 if s.shear else None
    assert s.A is not None and s.Iy is not None and s.Iz is not None and s.J is not None
    return Section(s.A, s.Iy, s.Iz, s.J, k, k)


def _fe_model(f: Flexible) -> NamedModel:
    """The FE model of the source with nodes at the interface points; ValueError if a point
    is off the beam or the panel."""
    if f.beam is not None:
        b = f.beam
        return straight_beam(
            b.start,
            b.end,
            _section(b.section),
            _material(b.material),
            b.elements,
            dict(f.interface),
            b.y_axis,
        )
    g = f.grillage
    assert g is not None
    ex = np.asarray(g.x) / np.linalg.norm(g.x)
    ey = np.asarray(g.y) - (np.asarray(g.y) @ ex) * ex
    ey /= np.linalg.norm(ey)
    axes = np.array([ex, ey, np.cross(ex, ey)])
    local = {}
    for name, point in f.interface.items():
        d = axes @ (np.asarray(point) - np.asarray(g.at))
        if abs(d[2]) > _IN_PLANE:
            raise ValueError(f"interface point {name} is {d[2]:.3g} m off the panel's plane")
        local[name] = (float(d[0]), float(d[1]))
    return grillage(
        g.size, g.thickness, _material(g.material), g.mesh, local, origin=g.at, axes=axes
    )


def flexible_component(f: Flexible) -> ModalComponent:
    """The modal component; ValueError (and ReductionError) say what is wrong."""
    return craig_bampton(
        _fe_model(f).model,
        modes=f.modes,
        frequency_range=f.frequency_range,
        fixed_interface_modes=f.fixed_interface_modes,
        damping=f.damping,
    )
