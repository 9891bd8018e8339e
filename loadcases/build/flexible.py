"""Flexible bodies of a mechanism file -> modal components (mechlib.flexible), issue 13.

Each `interface:` and `load_points:` point becomes a node of the FE model (and a point
`BODY.NAME` of the mechanism: loadcases.schema.mechanism); the Craig-Bampton reduction holds
the interface nodes (its boundary) and keeps the mode shapes of both.
"""

from __future__ import annotations

import importlib.util
from dataclasses import fields as _fields
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from loadcases.flexible.cache import cached
from loadcases.foundation.limits import local_path_problem
from loadcases.schema.flexible import BeamSection, FileSource, Flexible, MaterialModel
from mechlib.core.rotation import frame_axes
from mechlib.flexible.beam import Material, Section
from mechlib.flexible.craig_bampton import craig_bampton
from mechlib.flexible.fe_model import FEModel
from mechlib.flexible.grillage import NamedModel, grillage, straight_beam
from mechlib.flexible.invariants import Invariants
from mechlib.flexible.modal_component import ModalComponent
from mechlib.flexible.stiffening import ModalGeometric

__all__ = ["flexible_component", "flexible_fe_model"]

_IN_PLANE = 1e-6  # m: interface points farther than this from the panel's plane are errors
_AT_NODE = 1e-6  # m: an imported model's interface point lies this close to its node


def _kind(f: Flexible, name: str) -> str:
    """How the body names point `name` in messages."""
    return "interface point" if name in f.interface else "load point"


def _held_and_kept(named: NamedModel, f: Flexible) -> tuple[FEModel, list[int]]:
    """The FE model with only the interface points' nodes as its (Craig-Bampton) boundary,
    and the node indices of the load points, whose mode shapes are kept too."""
    interface = tuple(dict.fromkeys(named.nodes[name] for name in f.interface))
    kept = [named.nodes[name] for name in f.load_points if named.nodes[name] not in interface]
    return replace(named.model, interface=interface), kept


def _material(m: MaterialModel) -> Material:
    return Material(m.E, m.nu, m.rho)


def _section(s: BeamSection) -> Section:
    if s.width is not None and s.height is not None:
        return Section.rectangle(s.width, s.height, shear=s.shear)
    k = 5.0 / 6.0 if s.shear else None
    assert s.A is not None and s.Iy is not None and s.Iz is not None and s.J is not None
    return Section(s.A, s.Iy, s.Iz, s.J, k, k)


def _placed(model: FEModel, src: FileSource) -> FEModel:
    """The imported model in global axes at design: nodes moved to `at` + axes, K and M
    turned with them (u_model = axes u_global per nodal triple). ValueError when the axes
    turn a node that carries only part of a triple."""
    axes = frame_axes(src.x, src.y).T
    turn = sp.identity(len(model.dof_map), format="lil")
    if not np.allclose(axes, np.eye(3), rtol=0.0, atol=1e-15):
        row_of = {(int(n), int(c)): r for r, (n, c) in enumerate(model.dof_map)}
        for node in range(len(model.node_ids)):
            for first in (0, 3):
                present = [row_of[node, c] for c in range(first, first + 3) if (node, c) in row_of]
                if not present:
                    continue
                if len(present) != 3:
                    raise ValueError(
                        f"node {model.node_ids[node]} carries part of a "
                        f"{'translation' if first == 0 else 'rotation'} triple: the model can "
                        "only be used in its own axes (leave out x and y)"
                    )
                for i, r in enumerate(present):
                    for j, c in enumerate(present):
                        turn[r, c] = axes[i, j]
    t = turn.tocsr()
    return FEModel(
        model.node_ids,
        np.asarray(src.at) + model.coordinates @ axes,
        model.dof_map,
        (t.T @ model.stiffness @ t).tocsr(),
        (t.T @ model.mass @ t).tocsr(),
        model.interface,
    )


def _imported(f: Flexible, folder: Path) -> NamedModel:
    """The imported model placed in global axes, its interface nodes at the interface
    points; InputError for the files, ValueError for a point at no node."""
    from loadcases.flexible.read import read_fe_model

    src = f.file
    assert src is not None
    leaves = local_path_problem(src.path, folder, "the file that holds the mechanism")
    if leaves is not None:
        raise ValueError(leaves)
    model = _placed(read_fe_model(folder / src.path).model, src)
    nodes = {}
    for name, point in f.points().items():
        gaps = np.linalg.norm(model.coordinates - np.asarray(point), axis=1)
        node = int(np.argmin(gaps))
        if gaps[node] > _AT_NODE:
            raise ValueError(
                f"{_kind(f, name)} {name} is at no node of {src.path} (nearest: node "
                f"{model.node_ids[node]}, {gaps[node]:.3g} m away)"
            )
        if int(np.count_nonzero(model.dof_map[:, 0] == node)) != 6:
            raise ValueError(
                f"{_kind(f, name)} {name}: node {model.node_ids[node]} must carry all six DOF"
            )
        nodes[name] = node
    interface = tuple(dict.fromkeys(nodes.values()))
    return NamedModel(
        FEModel(
            model.node_ids,
            model.coordinates,
            model.dof_map,
            model.stiffness,
            model.mass,
            interface,
        ),
        nodes,
    )


def flexible_fe_model(f: Flexible, folder: Path) -> NamedModel:
    """The full FE model of a `flexible:` body before reduction (SI, global axes at design)
    with its named interface nodes (`loads flex check MECH --body NAME`); ValueError or
    InputError as `flexible_component`."""
    return _fe_model(f, folder)


def _fe_model(f: Flexible, folder: Path) -> NamedModel:
    """The FE model of the source with nodes at the interface points; ValueError if a point
    is off the beam or the panel or at no node of an imported model."""
    if f.file is not None:
        return _imported(f, folder)
    if f.beam is not None:
        b = f.beam
        return straight_beam(
            b.start,
            b.end,
            _section(b.section),
            _material(b.material),
            b.elements,
            f.points(),
            b.y_axis,
        )
    return _panel(f)


def _panel(f: Flexible) -> NamedModel:
    """A grillage or plate panel with nodes at the interface points; ValueError for a point
    off the panel or a plate without its optional extra."""
    g = f.grillage if f.grillage is not None else f.plate
    assert g is not None
    axes = frame_axes(g.x, g.y).T
    local = {}
    for name, point in f.points().items():
        d = axes @ (np.asarray(point) - np.asarray(g.at))
        if abs(d[2]) > _IN_PLANE:
            raise ValueError(f"{_kind(f, name)} {name} is {d[2]:.3g} m off the panel's plane")
        local[name] = (float(d[0]), float(d[1]))
    if f.plate is None:
        build = grillage
    elif importlib.util.find_spec("pyfe3d") is None:
        raise ValueError(
            "plate: the plate element comes from the optional package pyfe3d, which is not "
            "installed: pip install 'loads[plate]' (or pip install pyfe3d), or use grillage: "
            "with the same keys"
        )
    else:
        from mechlib.flexible.plate import plate as build
    return build(g.size, g.thickness, _material(g.material), g.mesh, local, origin=g.at, axes=axes)


def _arrays(component: ModalComponent) -> dict[str, np.ndarray]:
    """A modal component as named arrays (a cache entry)."""
    out = {f"inv_{f.name}": getattr(component.invariants, f.name) for f in _fields(Invariants)}
    out |= {f.name: getattr(component, f.name) for f in _fields(ModalComponent)}
    del out["invariants"], out["geometric"], out["held_frequency"]
    if component.geometric is not None:
        out |= {"geometric_spin": component.geometric.spin}
        out |= {"geometric_nodal": component.geometric.nodal}
    if component.held_frequency is not None:
        out["held_frequency"] = np.asarray(component.held_frequency)
    return out


def _component(arrays: dict[str, np.ndarray]) -> ModalComponent:
    """The modal component of a cache entry (`_arrays`); 0-d arrays back to floats."""
    values: dict[str, Any] = {k: float(v) if v.ndim == 0 else v for k, v in arrays.items()}
    invariants = Invariants(**{f.name: values[f"inv_{f.name}"] for f in _fields(Invariants)})
    optional = ("invariants", "geometric", "held_frequency")
    kept = {f.name: values[f.name] for f in _fields(ModalComponent) if f.name not in optional}
    geometric = (
        ModalGeometric(spin=values["geometric_spin"], nodal=values["geometric_nodal"])
        if "geometric_spin" in values
        else None
    )
    return ModalComponent(
        invariants=invariants,
        geometric=geometric,
        held_frequency=values.get("held_frequency"),
        **kept,
    )


def flexible_component(f: Flexible, folder: Path) -> ModalComponent:
    """The modal component (`folder`: that of the file holding the mechanism, where a
    `file:` source is read); ValueError (and ReductionError) say what is wrong, InputError
    what is wrong in an imported model's files. The reduction is cached
    (loadcases.flexible.cache) by its inputs and the engine's identity: a built-in beam,
    grillage or plate by its keys (the FE model is not even assembled on a hit), an imported
    model by its content (nodes, DOF map, K, M, interface), with the mode selection and damping; a
    set whose runs share a body reduces it once."""
    selection: dict[str, Any] = {
        "modes": f.modes,
        "frequency_range": f.frequency_range,
        "fixed_interface_modes": f.fixed_interface_modes,
        "damping": f.damping,
        "stiffening": f.stiffening,
    }
    imported = _held_and_kept(_fe_model(f, folder), f) if f.file is not None else None
    # the linear limit sets a warning only: a sweep of it reuses the reduction
    source = (
        {"fe_model": imported[0], "kept": imported[1]}
        if imported is not None
        else {"source": f.model_dump(exclude={"linear_limit"})}
    )

    def reduce() -> dict[str, np.ndarray]:
        model, kept = imported if imported is not None else _held_and_kept(_fe_model(f, folder), f)
        return _arrays(craig_bampton(model, keep_nodes=kept, **selection))

    return _component(cached({**source, **selection}, reduce))
