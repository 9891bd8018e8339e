"""A mechanism's numerical form, its topology: bodies and their indices, named points and
frames, joint coordinates, the constraint rows with their labels and owners, the force elements
bound to them, which rows are active, and the changes events make to them (SI units). Its
evaluation at a state is `mechlib.system.system.System`'s.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mechlib.core.rotation import rotation_matrix
from mechlib.elements import groups as element_groups
from mechlib.elements.states import ElementStates
from mechlib.flexible.attached import NodeWelds, attach_flexible, node_at, weld_labels
from mechlib.kinematics.constraints import Dot1, Dot2, Normalization, Spherical
from mechlib.kinematics.coordinate_block import CoordinateBlock
from mechlib.kinematics.coordinates import AngleMeasure, CoordinateEquation, TravelMeasure
from mechlib.kinematics.curve_joint import CurveEquation, CurvePoint
from mechlib.kinematics.kin import Kin
from mechlib.model.curves import Curve
from mechlib.model.joints import ROTATIONAL, TRANSLATIONAL, expand_joint, joint_frame
from mechlib.model.mechanism import GROUND, Mechanism

if TYPE_CHECKING:
    pass

__all__ = ["Topology", "coordinate_equations"]

_KINDS = {"spherical": Spherical, "dot1": Dot1, "dot2": Dot2}
_IDENTITY = np.eye(3)
_IDENTITY.flags.writeable = False
_MIN_LENGTH = 1e-3  # m


class _Held:
    """A coordinate held at a constant value (rad or m): the function of a lock."""

    constant = True  # no function of time: a compiled run reads its value once per call

    def __init__(self, value: float):
        self._value = value

    def hold(self, value: float) -> None:
        self._value = value

    def value(self, t: float) -> float:
        return self._value

    def rate(self, t: float) -> float:
        return 0.0

    def accel(self, t: float) -> float:
        return 0.0


class Topology:
    """What the rows and elements of a `Mechanism` are and which are active (module
    docstring); `System` evaluates them."""

    per_body = 7  # coordinates of a rigid body in q (mechlib.system.planar: 3)

    @property
    def normalisations(self) -> int:
        """Rows of `labels` that are Euler-parameter normalisations, not joints (one per
        body; mechlib.system.planar: none)."""
        return self.nb

    def __init__(self, mechanism: Mechanism):
        self.mechanism = mechanism
        self.body_names = list(mechanism.bodies)
        self.nb = len(self.body_names)
        self._index = {name: i for i, name in enumerate(self.body_names)}
        self._index[GROUND] = self.nb
        self._index |= {a: self._index[b] for a, b in mechanism.aliases.items()}
        self._points: dict[str, tuple[int, np.ndarray]] = {}  # named points found (point)
        self.flexible = attach_flexible(mechanism, self._index)
        self.nz = sum(a.body.n for a in self.flexible)
        self.nq = 7 * self.nb + self.nz
        bodies = [mechanism.bodies[n] for n in self.body_names]
        self.cm = np.vstack([np.array([b.cm for b in bodies]).reshape(-1, 3), np.zeros((1, 3))])
        rigid = [n not in mechanism.flexible for n in self.body_names]  # modal bodies: own M
        self.masses = np.array([b.mass if r else 0.0 for b, r in zip(bodies, rigid)])
        self.total_mass = float(sum(b.mass for b in bodies))
        self.inertia = np.ascontiguousarray(
            np.array([b.inertia if r else np.zeros((3, 3)) for b, r in zip(bodies, rigid)])
            .astype(float)
            .reshape(-1, 3, 3)
        )
        self.gravity = np.asarray(mechanism.gravity, dtype=float)
        self.pscale = 4.0 * np.trace(self.inertia, axis1=1, axis2=2) / 3.0
        self.measures: dict[tuple[str, str], AngleMeasure | TravelMeasure] = {}
        self._build_constraints()
        self.elements = list(mechanism.forces.values())
        self._remembering = [e for e in self.elements if hasattr(e, "commit")]
        self.states = ElementStates(self.elements)
        # geometric stiffening is loaded by the interface loads, the weld multipliers
        self.reaction_dependent = any(
            getattr(e, "uses_reactions", False) for e in self.elements
        ) or any(a.body.component.geometric is not None for a in self.flexible)
        self._dormant: list[int] = []  # rows that elements switch on when they need them
        self._locks: list[tuple[int, object]] = []  # (row, measure) of every lock made
        for element in self.elements:
            element.bind(self)
        self._groups, self._singles = element_groups.grouped(self.elements)
        awake = np.ones(len(self._all_labels), dtype=bool)
        awake[self._dormant] = False  # (np.setdiff1d would import numpy.ma: 9 ms)
        self.active = np.flatnonzero(awake)
        self._active_rows: tuple[np.ndarray | None, frozenset[int]] = (None, frozenset())
        self._force_rows: dict[str, tuple] = {}

    # ---- names -> indices -------------------------------------------------------------
    def body_index(self, name: str) -> int:
        return self._index[name]

    def frame_index(self, name: str) -> int | None:
        """None for ground axes, else the body whose axes a vector follows."""
        if name in self.mechanism.frames:
            name = self.mechanism.frames[name][0]
        return None if name == GROUND else self._index[name]

    def frame_axes(self, name: str, k: Kin) -> np.ndarray:
        """Columns: the axes of frame `name` (ground, a body or a named frame), global."""
        body, local, _ = self.mechanism.frames.get(name, (name, _IDENTITY, None))
        b = self._index[body]
        return local if b == self.nb else rotation_matrix(k.p[b]) @ local

    @property
    def length(self) -> float:
        """Characteristic size (m) of the mechanism at design: the extent of its body centres
        of mass and the origin (the ground), at least 1 mm."""
        return max(float(np.ptp(self.cm, axis=0).max(initial=0.0)), _MIN_LENGTH)

    def body_point(self, body: str, at) -> tuple[int, np.ndarray]:
        """(body index, body-fixed vector from its centre of mass) of a design point; on a
        flexible body, the node body of the kept node at that point."""
        if body in self.mechanism.flexible:
            body = node_at(self.mechanism.flexible[body], at)
        b = self._index[body]
        return b, np.asarray(at, dtype=float) - self.cm[b]

    def point(self, name: str) -> tuple[int, np.ndarray]:
        """(body index, body-fixed vector, read-only) of a named point, found once: the
        expressions of loads read points at every force evaluation."""
        found = self._points.get(name)
        if found is None:
            p = self.mechanism.points[name]
            b, s = self.body_point(p.body, p.at)
            s.flags.writeable = False
            found = self._points[name] = (b, s)
        return found

    def measure(self, joint: str, kind: str) -> AngleMeasure | TravelMeasure:
        try:
            return self.measures[(joint, kind)]
        except KeyError:
            raise KeyError(f"joint '{joint}' has no {kind} coordinate") from None

    # ---- construction -----------------------------------------------------------------
    def _build_constraints(self) -> None:
        rows: dict[str, list] = {k: [] for k in _KINDS}
        for joint in self.mechanism.joints.values():
            b1, s1 = self.body_point(joint.body1, joint.at)
            b2, s2 = self.body_point(joint.body2, joint.at)
            for row in expand_joint(joint, s1, s2):
                rows[row.kind].append((b1, b2, row.data, row.label, joint.name))
            if joint.type in ROTATIONAL + TRANSLATIONAL:
                fr = joint_frame(joint.axis)
                if joint.type in ROTATIONAL:
                    self.measures[(joint.name, "angle")] = AngleMeasure(b1, b2, fr.f, fr.g, fr.h)
                if joint.type in TRANSLATIONAL:
                    self.measures[(joint.name, "travel")] = TravelMeasure(b1, b2, fr.h, s1, s2)
        self.angle_measures = [m for m in self.measures.values() if isinstance(m, AngleMeasure)]
        self.norm = Normalization(self.nb)
        labels = [f"{n}: normalisation" for n in self.body_names]
        owners = list(self.body_names)
        self.groups: list = [self.norm]
        for kind, items in rows.items():
            if not items:
                continue
            bi, bj, data, lab, own = zip(*items)
            self.groups.append(_KINDS[kind](bi, bj, *map(np.array, zip(*data))))
            reps = 3 if kind == "spherical" else 1
            suffix = (" x", " y", " z") if reps == 3 else ("",)
            labels += [label + s for label in lab for s in suffix]
            owners += [o for o in own for _ in range(reps)]
        self._welds: tuple[NodeWelds, int] | None = None  # and its first row
        if self.flexible:
            welds = NodeWelds(self.flexible, self.nb)
            self._welds = (welds, sum(g.size for g in self.groups))
            self.groups.append(welds)
            labels += weld_labels(welds)
            owners += [a.name for a, _, _ in welds.items for _ in range(6)]
        self.coordinates = coordinate_equations(self)
        self._block: CoordinateBlock | None = None
        labels += [c.label for c in self.coordinates]
        owners += [c.owner for c in self.coordinates]
        self._all_labels, self._all_owners = labels, owners
        order = self.body_names + list(self.mechanism.joints) + list(self.mechanism.motions)
        self.owner_rank = {name: i for i, name in enumerate(order)}
        self.n_geometric = len(labels) - len(self.coordinates)

    def coordinate_of(self, joint: str, coordinate: str | None = None):
        if coordinate is not None:
            return self.measure(joint, coordinate)
        kind = "angle" if (joint, "angle") in self.measures else "travel"
        return self.measure(joint, kind)

    # ---- row selection ----------------------------------------------------------------
    @property
    def labels(self) -> list[str]:
        return [self._all_labels[i] for i in self.active]

    @property
    def owners(self) -> list[str]:
        return [self._all_owners[i] for i in self.active]

    def drop_rows(self, rows) -> None:
        """Remove equations (indices into the current rows), e.g. redundant ones."""
        self.active = np.delete(self.active, np.asarray(rows, dtype=int))
        self._pattern = None

    # ---- model changes by events --------------------------------------------------------
    def _rows_owned(self, owner: str) -> np.ndarray:
        return np.array([i for i, o in enumerate(self._all_owners) if o == owner], dtype=int)

    def set_active(self, name: str, active: bool) -> None:
        """Switch a force element (contacts included) or a motion on or off."""
        if name in self.mechanism.forces:
            self.mechanism.forces[name].active = active
            return
        rows = self._rows_owned(name)
        kept = np.setdiff1d(self.active, rows)
        self.active = np.union1d(kept, rows) if active else kept
        self._pattern = None

    def release(self, joint: str) -> None:
        """Remove a joint: its equations (and a lock of it) go; its reaction is zero."""
        self.active = np.setdiff1d(self.active, self._rows_owned(joint))
        self._pattern = None

    def lock(self, joint: str, k: Kin) -> int:
        """Freeze a joint's coordinate at its value in state `k` (a latch engaging); the
        row of the new equation (`let_go` frees it)."""
        measure = self.coordinate_of(joint)
        value = measure.value(k)
        eq = CoordinateEquation(
            [(1.0, measure)], f"{joint}: locked {measure.kind}", joint, _Held(value)
        )
        self.active = _with_lock(self, eq, measure)
        self._pattern = None
        return self._locks[-1][0]

    def locked(self, measure) -> bool:
        """Whether a lock (an event's, a phase's) holds coordinate `measure` now."""
        return any(m is measure and self.is_active(row) for row, m in self._locks)

    def held_coordinate(self, owner: str, measure) -> int:
        """A dormant equation `measure = held value`, owned by `owner` (a joint friction
        sticking): its row index among all equations, for `hold` and `let_go`."""
        eq = CoordinateEquation(
            [(1.0, measure)], f"{owner}: stuck {measure.kind}", owner, _Held(0.0)
        )
        self.coordinates.append(eq)
        self._all_labels.append(eq.label)
        self._all_owners.append(owner)
        self._dormant.append(len(self._all_labels) - 1)
        return len(self._all_labels) - 1

    def hold(self, row: int, k: Kin) -> None:
        """Switch on held-coordinate equation `row` at its coordinate's value in `k`."""
        eq = self.coordinates[row - self.n_geometric]
        if not (isinstance(eq, CoordinateEquation) and isinstance(eq.function, _Held)):
            raise ValueError(f"equation {row} ({eq.label}) is not a held coordinate")
        eq.function.hold(eq.terms[0][1].value(k))
        self.active = np.union1d(self.active, [row])
        self._pattern = None

    def let_go(self, row: int) -> None:
        """Switch off held-coordinate equation `row`."""
        self.active = np.setdiff1d(self.active, [row])
        self._pattern = None

    def is_active(self, row: int) -> bool:
        """Whether equation `row` is switched on (joint friction asks at every force
        evaluation: a set of the active rows, made again when they change, not np.isin's
        38 us)."""
        active, rows = self._active_rows
        if active is not self.active:
            active, rows = self.active, frozenset(self.active.tolist())
            self._active_rows = (active, rows)
        return row in rows

    def snapshot(self) -> dict:
        """What outputs need to read a recorded state as it was: angle references, active
        equations and elements."""
        return {
            "angles": self.references(),
            "active": self.active,
            "elements": {n: e.active for n, e in self.mechanism.forces.items()},
            "states": self.states.z.copy(),
            "anchors": {
                e.name: e.static_anchor() for e in self._remembering if hasattr(e, "static_anchor")
            },
        }

    def restore_snapshot(self, snap: dict) -> None:
        self.restore(snap["angles"])
        self.active = snap["active"]
        for name, flag in snap["elements"].items():
            self.mechanism.forces[name].active = flag
        self.states.trial = snap["states"]
        for name, anchor in snap.get("anchors", {}).items():
            self.mechanism.forces[name].restore_static_anchor(anchor)

    def joint_force_rows(self, joint: str) -> tuple[np.ndarray, int, float]:
        """(rows among the active equations, moving body index, sign) of `joint`'s own
        equations: the force on its body 1 is sign * -(phi_q[rows, r of body])^T lam[rows]
        (body 2, sign -1, when body 1 is ground)."""
        cached = self._force_rows.get(joint)
        if cached is not None and cached[0] is self.active:
            return cached[1]
        j = self.mechanism.joints[joint]
        sign, body = (1.0, j.body1) if j.body1 != GROUND else (-1.0, j.body2)
        rows = np.array([i for i, o in enumerate(self.owners) if o == joint], dtype=int)
        found = (rows, self._index[body], sign)
        self._force_rows[joint] = (self.active, found)
        return found

    def design_q(self) -> np.ndarray:
        q = np.zeros((self.nb, 7))
        q[:, :3] = self.cm[:-1]
        q[:, 3] = 1.0
        return np.r_[q.ravel(), np.zeros(self.nz)]

    def _select(self, rows: np.ndarray) -> np.ndarray:
        """The active rows (all of them, without a copy, unless some were dropped)."""
        return rows if self.active.size == len(self._all_labels) else rows[self.active]

    def coordinate_rows(self) -> CoordinateBlock:
        """The coordinate equations as one block, rebuilt when an event added one."""
        block = self._block
        if block is None or block.size != len(self.coordinates):
            block = self._block = CoordinateBlock(self.coordinates)
        return block

    def references(self) -> dict:
        """Unwrapping references of the joint angles, to restore with `restore`."""
        return {key: getattr(m, "reference", 0.0) for key, m in self.measures.items()}

    def restore(self, references: dict) -> None:
        for key, value in references.items():
            measure = self.measures[key]
            if isinstance(measure, AngleMeasure):
                measure.reference = value


def _with_lock(topology: Topology, eq: CoordinateEquation, measure) -> np.ndarray:
    """Add lock `eq` of coordinate `measure` to `topology`'s equations (recorded in its
    locks); the active rows with it, without the rows that held the coordinate (a joint
    friction's stick): the lock supersedes them (the same equation twice; a locked joint
    cannot slip)."""
    topology.coordinates.append(eq)
    topology._all_labels.append(eq.label)
    topology._all_owners.append(eq.owner)
    row = len(topology._all_labels) - 1
    topology._locks.append((row, measure))
    first = topology.n_geometric
    held = []
    for r in topology._dormant:
        other = topology.coordinates[r - first]
        if isinstance(other, CoordinateEquation) and other.terms[0][1] is measure:
            held.append(r)
    return np.append(np.setdiff1d(topology.active, held), row)


def coordinate_equations(topology: Topology) -> list[CoordinateEquation | CurveEquation]:
    """The coordinate equations of screws, couplers, gears, points on curves and motions."""
    eqs: list[CoordinateEquation | CurveEquation] = []
    for j in topology.mechanism.joints.values():
        if j.type == "screw":
            terms = [
                (1.0, topology.measure(j.name, "travel")),
                (-j.required(j.pitch, "pitch") / (2.0 * np.pi), topology.measure(j.name, "angle")),
            ]
            eqs.append(CoordinateEquation(terms, f"{j.name}: screw travel-angle", j.name))
        elif j.type in ("coupler", "gear"):
            a, b = j.required(j.joints, "joints")
            terms = [(-j.ratio, topology.coordinate_of(a)), (1.0, topology.coordinate_of(b))]
            eqs.append(CoordinateEquation(terms, f"{j.name}: coupling {a}-{b}", j.name))
        elif j.type == "point_on_curve":
            eqs += curve_equations(topology, j)
    for m in topology.mechanism.motions.values():
        measure = topology.coordinate_of(m.joint, m.coordinate)
        label = f"{m.name}: {measure.kind} of {m.joint}"
        eqs.append(CoordinateEquation([(1.0, measure)], label, m.name, m.function))
    return eqs


def curve_equations(topology: Topology, j) -> list[CurveEquation]:
    """The two equations keeping joint point `at` of body 1 on the curve of body 2."""
    bi, si = topology.body_point(j.body1, j.at)
    bj = topology._index[j.body2]
    curve = Curve([topology.body_point(j.body2, p)[1] for p in j.curve], j.interpolation)
    point = CurvePoint(bi, bj, si, curve)
    return [
        CurveEquation(point, 0, f"{j.name}: off the curve, in its plane", j.name),
        CurveEquation(point, 1, f"{j.name}: off the curve, across its plane", j.name),
    ]
