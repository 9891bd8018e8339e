"""Section loads (`sections:` of a mechanism, `{section: NAME}` requests of a case): the body
cut at the section, its kept part a body of its own welded to the rest by a fixed joint at
the section point, whose reaction is the section's loads.

This is the split-body model an analyst builds by hand (thesis seed 000, 5.5: split the
shaft at the bolt hole, join both halves by a fixed joint, measure it in axes that turn with
the shaft), made from the mechanism only when a case requests the section (otherwise the
body is not cut: nothing is paid). The kept part (the side of the plane of `side`, else the
side the normal points out of) takes the section's own mass properties; the rest of the
body keeps the remainder: m_r = m - m_k, c_r = (m c - m_k c_k) / m_r and, about c_r,
I_r = I - (I_k + m_k [d_k]) - m_r [d_r] with [d] = |d|^2 E - d d^T, d = c_i - c (parallel
axis theorem). Joints, points, frames and point forces of the body go to the part their
point is on (a point on the plane stays with the rest); anything that holds the body
itself (a body torque, a seal, a bushing, a contact) cannot be put on one side: an error.
The fixed joint's reaction (`ml.JointReaction`, on the kept part from the rest, at the
section point) in the axes of the body (default) or any frame is the request's output.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence

import numpy as np

from loadcases.schema.mechanism import Body, Fixed, FlexibleBody, MechanismModel, Section
from mechlib import GROUND

__all__ = [
    "inertia_tensor",
    "inertia_values",
    "kept_body",
    "section_joint",
    "split_sections",
]

Problem = Callable[[str, str], None]  # (key in the mechanism file, message)
_PLANE = 1e-12  # m: a point this close to the plane is on it (stays with the rest)
_NEGATIVE = 1e-9  # of the body's largest moment: below -this the rest's inertia is not real


def section_joint(name: str) -> str:
    """The name of the fixed joint that carries section `name`'s loads."""
    return f"section:{name}"


def kept_body(name: str, section: Section) -> str:
    """The name of section `name`'s kept part."""
    return f"{section.body}|{name}"


def inertia_tensor(values: Sequence[float]) -> np.ndarray:
    """[Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (Ixy = -integral x y dm) -> (3, 3)."""
    ixx, iyy, izz, *products = (float(v) for v in values)
    ixy, ixz, iyz = products if products else (0.0, 0.0, 0.0)
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


def inertia_values(tensor: np.ndarray) -> tuple[float, ...]:
    """(3, 3) -> [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]."""
    t = tensor
    return (t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2])


def _shift(mass: float, d: np.ndarray) -> np.ndarray:
    return mass * (d @ d * np.eye(3) - np.outer(d, d))


def _rest(body: Body, section: Section, key: str, problem: Problem) -> Body | None:
    """The body less the kept part, or None after a problem."""
    m, c, inertia = body.mass, np.asarray(body.cm), inertia_tensor(body.inertia)
    mk = section.mass
    ck = np.asarray(section.cm if section.cm is not None else section.at, dtype=float)
    mr = m - mk
    if mr <= 0.0:
        problem(f"{key}.mass", f"the kept part's {mk:g} kg is not less than the body's {m:g} kg")
        return None
    cr = (m * c - mk * ck) / mr
    ir = inertia - inertia_tensor(section.inertia) - _shift(mk, ck - c) - _shift(mr, cr - c)
    if np.linalg.eigvalsh(ir).min() < -_NEGATIVE * max(np.abs(inertia).max(), 1.0):
        problem(f"{key}.inertia", "the kept part's inertia leaves the rest of the body none")
        return None
    return Body(mass=mr, cm=tuple(cr), inertia=inertia_values(ir))


class _Cut:
    """Which side of a section's plane a point is on."""

    def __init__(self, section: Section) -> None:
        self.at = np.asarray(section.at, dtype=float)
        self.n = np.asarray(section.normal, dtype=float) / np.linalg.norm(section.normal)
        side = section.side
        self.sign = -1.0 if side is None else np.sign((np.asarray(side) - self.at) @ self.n)

    def kept(self, point: Iterable[float]) -> bool:
        distance = (np.asarray(tuple(point), dtype=float) - self.at) @ self.n
        return bool(self.sign * distance > _PLANE)


def _moved(items: dict, body: str, kept: str, cut: _Cut, key: str, problem: Problem) -> dict:
    """Joints, points, frames or force elements, those of `body` on the kept side moved to
    `kept`; one that holds the body without a point: a problem."""
    out = {}
    for name, item in items.items():
        bodies = getattr(item, "bodies", None)
        single = getattr(item, "body", None)
        if single != body and not (isinstance(bodies, (list, tuple)) and body in bodies):
            out[name] = item
            continue
        at = getattr(item, "at", None)
        if at is None or (bodies is not None and not hasattr(item, "at")):
            problem(
                f"{key}.{name}",
                f"holds body '{body}' without a point: it cannot be put on one side of a "
                "section of it",
            )
            out[name] = item
            continue
        if not cut.kept(at):
            out[name] = item
        elif single == body:
            out[name] = item.model_copy(update={"body": kept})
        else:
            pair = tuple(kept if b == body else b for b in bodies or ())
            out[name] = item.model_copy(update={"bodies": pair})
    return out


def split_sections(mech: MechanismModel, names: Iterable[str], problem: Problem) -> MechanismModel:
    """The mechanism with the body of each section in `names` cut there (module notes)."""
    for name in dict.fromkeys(names):
        section = mech.sections[name]
        key, body = f"sections.{name}", mech.bodies.get(section.body)
        if body is None or isinstance(body, FlexibleBody) or section.body == GROUND:
            problem(f"{key}.body", f"'{section.body}' is not a rigid body: it cannot be cut")
            continue
        rest = _rest(body, section, key, problem)
        if rest is None:
            continue
        kept, cut = kept_body(name, section), _Cut(section)
        cm = section.cm if section.cm is not None else section.at
        bodies = dict(mech.bodies)
        bodies[section.body] = rest
        bodies[kept] = Body(mass=section.mass, cm=cm, inertia=section.inertia)
        joints = _moved(dict(mech.joints), section.body, kept, cut, "joints", problem)
        joints[section_joint(name)] = Fixed(
            type="fixed", bodies=(kept, section.body), at=section.at
        )
        mech = mech.model_copy(
            update={
                "bodies": bodies,
                "joints": joints,
                "points": _moved(dict(mech.points), section.body, kept, cut, "points", problem),
                "frames": _moved(dict(mech.frames), section.body, kept, cut, "frames", problem),
                "forces": _moved(dict(mech.forces), section.body, kept, cut, "forces", problem),
                "contacts": _moved(
                    dict(mech.contacts), section.body, kept, cut, "contacts", problem
                ),
            }
        )
    return mech
