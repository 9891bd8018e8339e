"""A mechanism compiled to arrays: constraint equations, mass matrix, applied forces.

Symbols (7 coordinates per moving body, ground excluded): ``phi`` (m,) residuals,
``phi_q`` (m, nq) Jacobian, ``nu`` right side of ``phi_q qd = nu``, ``gamma`` right side of
``phi_q qdd = gamma``, ``M`` (nq, nq), ``Q`` (nq,) generalised applied forces, and the
equations of motion ``M qdd + phi_q^T lam = Q``. Row `i` of every constraint array is
labelled ``labels[i]`` and belongs to joint or motion ``owners[i]``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mechlib.core import jit
from mechlib.core.rotation import e_matrix, rotation_matrix
from mechlib.elements import groups as element_groups
from mechlib.elements.states import ElementStates
from mechlib.flexible.attached import NodeWelds, attach_flexible, node_at, weld_labels
from mechlib.kinematics import kernels
from mechlib.kinematics.constraint_arrays import ConstraintArrays
from mechlib.kinematics.constraints import Dot1, Dot2, Normalization, Spherical
from mechlib.kinematics.coordinate_block import CoordinateBlock
from mechlib.kinematics.coordinates import AngleMeasure, CoordinateEquation, TravelMeasure
from mechlib.kinematics.curve_joint import CurveEquation, CurvePoint
from mechlib.kinematics.kin import Kin
from mechlib.kinematics.view import StateView
from mechlib.model.curves import Curve
from mechlib.model.joints import ROTATIONAL, TRANSLATIONAL, expand_joint, joint_frame
from mechlib.model.mechanism import GROUND, Mechanism

if TYPE_CHECKING:
    from mechlib.linalg.factor import SaddlePattern

__all__ = ["System"]

_KINDS = {"spherical": Spherical, "dot1": Dot1, "dot2": Dot2}
_IDENTITY = np.eye(3)
_IDENTITY.flags.writeable = False
_NO_GRAVITY = np.zeros(3)
_MIN_LENGTH = 1e-3  # m


class _Held:
    """A coordinate held at a constant value (rad or m): the function of a lock."""

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


class System:
    """The numerical form of a `Mechanism` (see module docstring for the symbols)."""

    per_body = 7  # coordinates of a rigid body in q (mechlib.system.planar: 3)
    _pattern: SaddlePattern | None = None  # the saddle matrix's sparsity, found on first use

    @property
    def normalisations(self) -> int:
        """Rows of `labels` that are Euler-parameter normalisations, not joints (one per
        body; mechlib.system.planar: none)."""
        return self.nb

    def __init__(self, mechanism: Mechanism):
        self.mechanism = mechanism
        self._arrays: ConstraintArrays | bool | None = False  # packed_constraints(), once
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
        self.reaction_dependent = any(getattr(e, "uses_reactions", False) for e in self.elements)
        self._no_wrench = np.zeros((self.nb + 1, 3))
        self._no_wrench.flags.writeable = False
        self._dormant: list[int] = []  # rows that elements switch on when they need them
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

    def frame_origin(self, name: str, k: Kin) -> np.ndarray:
        """Origin (m, global) of frame `name`: a named frame's `at`; a body's frame is the
        body-fixed point that was at the global origin at design (CAD axes moving along)."""
        body, _, at = self.mechanism.frames.get(name, (name, None, (0.0, 0.0, 0.0)))
        b, s = self.body_point(body, at)
        return self.view(k).point_position(b, s)

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
        self.coordinates = self._coordinate_equations()
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

    def _coordinate_equations(self) -> list[CoordinateEquation | CurveEquation]:
        eqs: list[CoordinateEquation | CurveEquation] = []
        for j in self.mechanism.joints.values():
            if j.type == "screw":
                terms = [
                    (1.0, self.measure(j.name, "travel")),
                    (-j.required(j.pitch, "pitch") / (2.0 * np.pi), self.measure(j.name, "angle")),
                ]
                eqs.append(CoordinateEquation(terms, f"{j.name}: screw travel-angle", j.name))
            elif j.type in ("coupler", "gear"):
                a, b = j.required(j.joints, "joints")
                terms = [(-j.ratio, self.coordinate_of(a)), (1.0, self.coordinate_of(b))]
                eqs.append(CoordinateEquation(terms, f"{j.name}: coupling {a}-{b}", j.name))
            elif j.type == "point_on_curve":
                eqs += self._curve_equations(j)
        for m in self.mechanism.motions.values():
            measure = self.coordinate_of(m.joint, m.coordinate)
            label = f"{m.name}: {measure.kind} of {m.joint}"
            eqs.append(CoordinateEquation([(1.0, measure)], label, m.name, m.function))
        return eqs

    def _curve_equations(self, j) -> list[CurveEquation]:
        """The two equations keeping joint point `at` of body 1 on the curve of body 2."""
        bi, si = self.body_point(j.body1, j.at)
        bj = self._index[j.body2]
        curve = Curve([self.body_point(j.body2, p)[1] for p in j.curve], j.interpolation)
        point = CurvePoint(bi, bj, si, curve)
        return [
            CurveEquation(point, 0, f"{j.name}: off the curve, in its plane", j.name),
            CurveEquation(point, 1, f"{j.name}: off the curve, across its plane", j.name),
        ]

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

    def lock(self, joint: str, k: Kin) -> None:
        """Freeze a joint's coordinate at its value in state `k` (a latch engaging)."""
        measure = self.coordinate_of(joint)
        value = measure.value(k)
        eq = CoordinateEquation(
            [(1.0, measure)], f"{joint}: locked {measure.kind}", joint, _Held(value)
        )
        self.coordinates.append(eq)
        self._all_labels.append(eq.label)
        self._all_owners.append(joint)
        self.active = np.append(self.active, len(self._all_labels) - 1)
        self._pattern = None

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

    # ---- evaluation ---------------------------------------------------------------------
    def kin(self, q: np.ndarray, qd: np.ndarray | None = None, t: float = 0.0) -> Kin:
        return Kin.from_state(q, qd, t, self.nz)

    def body_columns(self, rows: np.ndarray) -> np.ndarray:
        """Working Jacobian rows (..., 7 (nb + 1) + nz) without ground's columns (..., nq)."""
        if not self.nz:
            return rows[..., : self.nq]
        cut = 7 * self.nb
        return np.concatenate([rows[..., :cut], rows[..., cut + 7 :]], axis=-1)

    def coordinate_gradient(self, measure, k: Kin) -> np.ndarray:
        """d(measure)/dq (nq,) of a joint angle or travel (mechlib.kinematics.coordinates)."""
        return self.body_columns(measure.gradient(k))

    def body_rates(self, k: Kin, body: int) -> np.ndarray:
        """(6, nq): qd -> the velocity (m/s) and angular velocity (rad/s) of `body`, global."""
        block = np.zeros((6, self.nq))
        block[:3, 7 * body : 7 * body + 3] = np.eye(3)
        block[3:, 7 * body + 3 : 7 * body + 7] = 2.0 * e_matrix(k.p[body])
        return block

    def state_of(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        """(q, qd) (nq,) of state `k`: the inverse of `kin`."""
        return np.r_[k.x[:-1].ravel(), k.z], np.r_[k.xd[:-1].ravel(), k.zd]

    def body_weights(self, translation: float, rotation: float) -> np.ndarray:
        """Per-body weights (7,) of q's entries: `translation` for r, `rotation` (the size
        of one radian) for the Euler parameters, which change by half an angle."""
        return np.r_[np.full(3, translation), np.full(4, rotation)]

    def cm_positions(self, q: np.ndarray) -> np.ndarray:
        """Centres of mass (nb, 3), m, global, of the rigid coordinates of q."""
        return q[: 7 * self.nb].reshape(self.nb, 7)[:, :3].copy()

    def cm_forces(self, generalized: np.ndarray) -> np.ndarray:
        """The force parts (nb, 3), N, global, of generalised forces (nq,)."""
        return generalized[: 7 * self.nb].reshape(self.nb, 7)[:, :3]

    def reaction_coupling(self, coupling: np.ndarray, k: Kin) -> np.ndarray:
        """dQ/dlam (nq, m) of elements that wrote it in this system's coordinates."""
        return coupling

    def output_notes(self, reactions: bool) -> list[str]:
        """What the outputs asked for (`reactions`: joint reactions among them) leave out
        (mechlib.system.planar: out-of-plane reactions)."""
        return []

    def in_space(self, trajectory):
        """(the 3-D system, the trajectory in its coordinates) to evaluate outputs on: this
        system and `trajectory` (mechlib.system.planar lifts its own)."""
        return self, trajectory

    def view(
        self, k: Kin, lam: np.ndarray | None = None, jac: np.ndarray | None = None
    ) -> StateView:
        return StateView(self, k, lam, jac)

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

    def phi(self, k: Kin) -> np.ndarray:
        arrays = self.packed_constraints()
        if arrays is not None:
            return arrays.phi(k)
        parts = [g.phi(k) for g in self.groups] + [self.coordinate_rows().phi(k)]
        return self._select(np.concatenate(parts))

    def packed_constraints(self) -> ConstraintArrays | None:
        """The constraint equations packed for one compiled call
        (mechlib.kinematics.constraint_arrays), once the kernels are compiled; None where the
        system needs the grouped path (flexible bodies, curve joints) or the kernels run
        as Python (`loads validate`)."""
        if not jit.compiled():
            return None
        if self._arrays is False:
            self._arrays = ConstraintArrays(self) if ConstraintArrays.eligible(self) else None
        return self._arrays  # type: ignore[return-value]

    def phi_and_jacobian(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        """(phi, phi_q): one compiled call (`packed_constraints`) or one pass over the
        primitive groups."""
        arrays = self.packed_constraints()
        if arrays is not None:
            return arrays.phi_and_jacobian(k)
        return self.grouped_phi_and_jacobian(k)

    def grouped_phi_and_jacobian(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        """(phi, phi_q) by one compiled call per primitive group and the coordinate block
        (the path of every system; the reference of the packed one)."""
        out = np.zeros((len(self._all_labels), k.ncol))
        parts, row = [], 0
        for g in self.groups:
            parts.append(g.phi(k))
            g.jacobian(k, out[row : row + g.size])
            row += g.size
        block = self.coordinate_rows()
        sines = block.sines(k)
        parts.append(block.phi(k, sines))
        block.jacobian(k, out[row:], sines)
        return self._select(np.concatenate(parts)), self.body_columns(self._select(out))

    def phi_q(self, k: Kin) -> np.ndarray:
        arrays = self.packed_constraints()
        if arrays is not None:
            return arrays.phi_and_jacobian(k)[1]
        out = np.zeros((len(self._all_labels), k.ncol))
        row = 0
        for g in self.groups:
            g.jacobian(k, out[row : row + g.size])
            row += g.size
        self.coordinate_rows().jacobian(k, out[row:])
        return self.body_columns(self._select(out))

    def nu(self, k: Kin) -> np.ndarray:
        out = np.zeros(len(self._all_labels))
        if self.coordinates:
            out[self.n_geometric :] = [c.nu(k.t) for c in self.coordinates]
        return self._select(out)

    def gamma(self, k: Kin) -> np.ndarray:
        arrays = self.packed_constraints()
        if arrays is not None:
            return arrays.nu_and_gamma(k)[1]
        parts = [g.gamma(k) for g in self.groups]
        parts.append(self.coordinate_rows().gamma(k))
        return self._select(np.concatenate(parts))

    def commit(self, k: Kin) -> None:
        """Accept a state: joint angles unwrap against it from now on, and elements with a
        memory (`commit(view)`: a contact's approach speed, a stick point) update it."""
        arrays = self.packed_constraints()
        if arrays is not None:
            arrays.commit_angles(k)
        else:
            for m in self.angle_measures:
                m.commit(k)
        if self._remembering:
            view = self.view(k)
            for element in self._remembering:
                element.commit(view)

    def begin(self, k: Kin) -> None:
        """Start of an analysis at state `k`: elements with a memory of where they began
        (`begin(view)`: a joint friction's stick anchor) take it from there."""
        view = self.view(k)
        for element in self._remembering:
            if hasattr(element, "begin"):
                element.begin(view)

    def saddle_pattern(self):
        """Sparsity of [[M, phi_q^T], [phi_q, 0]], from a generic state (found once)."""
        if self._pattern is None:
            from mechlib.linalg.factor import SaddlePattern

            rng = np.random.default_rng(7)
            q = self.design_q() + 0.1 * rng.standard_normal(self.nq)
            k = self.kin(q, rng.standard_normal(self.nq), 0.0)
            self._pattern = SaddlePattern(self.mass(k), self.phi_q(k))
        return self._pattern

    def references(self) -> dict:
        """Unwrapping references of the joint angles, to restore with `restore`."""
        return {key: getattr(m, "reference", 0.0) for key, m in self.measures.items()}

    def restore(self, references: dict) -> None:
        for key, value in references.items():
            measure = self.measures[key]
            if isinstance(measure, AngleMeasure):
                measure.reference = value

    def mass(self, k: Kin) -> np.ndarray:
        """Mass matrix M (nq, nq): m I for r; 4 G^T J' G (+ a p p^T term fixing |p|) for p."""
        out = np.zeros((self.nq, self.nq))
        kernels.mass_matrix(k.x, self.masses, self.inertia, self.pscale, out)
        for a in self.flexible:
            cols = a.columns(self.nb)
            out[np.ix_(cols, cols)] += a.mass(k)
        return out

    def mass_times(self, k: Kin, x: np.ndarray) -> np.ndarray:
        """M(q) x without forming M (nq,)."""
        out = np.empty(self.nq)
        if self.nz:
            return self.mass(k) @ x
        kernels.mass_times(k.x, self.masses, self.inertia, self.pscale, x, out)
        return out

    def wrenches(
        self, k: Kin, lam: np.ndarray | None = None, skip=(), jac: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Forces F and torques N (nb+1, 3) of the active force elements (but those whose
        id is in `skip`), global axes, through the cm; `lam` (the multipliers of the
        iterate) for elements that depend on joint reactions (joint friction), `jac` its
        phi_q when known."""
        if not self.elements:
            return self._no_wrench, self._no_wrench
        F = np.zeros((self.nb + 1, 3))
        N = np.zeros((self.nb + 1, 3))
        for group in self._groups:  # one call per element type (mechlib.elements.groups)
            group.apply(k.x, k.xd, skip, F, N)
        view = StateView(self, k, lam, jac, memo=True)  # one state for all elements
        for element in self._singles:
            if element.active and not (skip and id(element) in skip):
                element.apply(view, F, N)
        return F, N

    def forces(
        self,
        k: Kin,
        *,
        inertia: bool = True,
        lam: np.ndarray | None = None,
        skip=(),
        jac: np.ndarray | None = None,
    ) -> np.ndarray:
        """Q (nq,): gravity, elements (but those whose id is in `skip`) and, with
        `inertia`, the quadratic velocity terms (`lam`, `jac`: see `wrenches`)."""
        F, N = self.wrenches(k, lam, skip, jac)
        out = np.zeros(self.nq)
        kernels.body_forces(k.x, k.xd, self.masses, self.inertia, self.gravity, F, N, inertia, out)
        for a in self.flexible:
            stiff = a.body.component.geometric is not None
            loads = self.node_loads(k, lam, a) if stiff else None
            out[a.columns(self.nb)] += a.forces(k, self.gravity, inertia, loads)
        return out

    def node_loads(self, k: Kin, lam: np.ndarray | None, a) -> np.ndarray | None:
        """The loads (k, 6) on modal body `a` at its kept nodes from the weld multipliers
        among `lam` (the active rows), None when no multipliers are known."""
        if lam is None or self._welds is None or len(lam) != self.active.size:
            return None
        welds, first = self._welds
        full = np.zeros(len(self._all_labels))
        full[self.active] = lam
        return welds.node_loads(k, full[first : first + welds.size], a)

    def generalized(self, k: Kin, F: np.ndarray, N: np.ndarray) -> np.ndarray:
        """Q (nq,) of forces F and torques N (nb+1, 3) alone (no gravity, no inertia)."""
        out = np.zeros(self.nq)
        kernels.body_forces(k.x, k.xd, self.masses, self.inertia, _NO_GRAVITY, F, N, False, out)
        return out
