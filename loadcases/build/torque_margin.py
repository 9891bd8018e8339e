"""Torque margin of hinge lines along a run (seed 003 section 2.1, eq. 2.1).

For each hinge line j and each result row: every contributor's torque about the hinge line,
positive in the deployment direction, is driving when positive and resistive when
negative (a harness may be either along the deployment, seed 2.2.4). Then
    D_j = sum of driving torques,  R_j = sum of factor_i * |resistive torque_i|,
    TM_j = D_j / R_j  (required: `required`, default 2),
and the restart check of a deployment stopped part-way (seed 2.1): from rest no damper and
no inertia torque resists, friction is multiplied by `restart_friction` (breakaway).

Torques come from the force elements' own outputs (`value`: moment resisting a positive
joint angle; joint friction: its capacity mu r F_r + T_pret, eq. 2.2, always resisting) or
from an expression (N*m, positive resisting). Columns `tm_HL.driving`, `tm_HL.resistive`
(N*m, factors included), `tm_HL.ratio`, `tm_HL.restart_ratio` (-), `tm_HL.excess`
(D - required R, N*m) and `tm_HL.angle` (deployment angle, rad) are added to the run.
"""

from __future__ import annotations

import dataclasses
import difflib
from dataclasses import dataclass, field

import numpy as np

import mechlib as ml
from loadcases.build.context import Guarded
from loadcases.build.system_margin import SYSTEM_LINE, reduced_to_first
from loadcases.expressions import ExpressionError, parse
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.schema.torque_margin import DEFAULT_FACTORS
from mechlib.model.tables import Table

__all__ = ["TM_PREFIX", "TM_UNITS", "MarginPlan", "plan_torque_margin"]

TM_PREFIX = "tm_"
TM_UNITS = {
    "driving": "N*m",
    "resistive": "N*m",
    "ratio": "",
    "restart_ratio": "",
    "excess": "N*m",
    "angle": "rad",
}
_HIDDEN = "_tm_"  # requests the margin reads, removed from the results afterwards
_ELEMENT_TYPES = ("torsion_spring", "joint_friction", "damper")
_RATE_KINDS = ("damper", "inertia")  # nothing of them resists a restart from rest


@dataclass(frozen=True)
class _Term:
    label: str
    kind: str
    factor: float
    column: str  # channel with the torque (positive resisting a positive joint angle)
    friction: bool
    # damper: the channel is omega, the torque c * omega;
    # joint friction: its capacity always resists
    scale: float = 1.0


@dataclass
class _Line:
    name: str
    sense: float
    angle_column: str
    terms: list[_Term] = field(default_factory=list)
    rate_column: str = ""  # its deployment rate, read by the system margin only


@dataclass
class MarginPlan:
    """The hinge lines of a case's `torque_margin:` and the requests their torques need."""

    required: float
    restart_friction: float
    lines: list[_Line]
    requests: list
    system: bool = False  # also the system margin (loadcases.build.system_margin)

    def units(self) -> dict[str, str]:
        """Unit of every column the margin adds."""
        names = [line.name for line in self.lines] + ([SYSTEM_LINE] if self.system else [])
        return {f"{TM_PREFIX}{name}.{c}": u for name in names for c, u in TM_UNITS.items()}

    def apply(self, solution: ml.Solution) -> tuple[ml.Solution, dict, list[str]]:
        """The solution with the margin columns (hidden ones removed), the summary block
        `torque_margin` and notes (a failed check, rows without a resistive torque)."""
        channels = {k: v for k, v in solution.channels.items() if not k.startswith(_HIDDEN)}
        hinge_lines: dict[str, dict] = {}
        block = {"required": self.required, "passed": True, "hinge_lines": hinge_lines}
        notes = []
        sums = []
        for line in self.lines:
            sums.append(_line_torques(line, solution, self.restart_friction))
            angle = line.sense * solution.channels[line.angle_column]
            columns, summary = _margin(*sums[-1], angle, solution.time, self.required)
            channels.update({f"{TM_PREFIX}{line.name}.{c}": v for c, v in columns.items()})
            hinge_lines[line.name] = summary
            block["passed"] = block["passed"] and summary["passed"] and solution.ok
            notes += _line_notes(line.name, summary, self.required)
        if self.system:
            # beside the per-line check of eq. 2.1, which alone decides `passed`
            rates = [line.sense * solution.channels[line.rate_column] for line in self.lines]
            first = self.lines[0]
            angle = first.sense * solution.channels[first.angle_column]
            columns, summary = _margin(
                *reduced_to_first(sums, rates), angle, solution.time, self.required
            )
            channels.update({f"{TM_PREFIX}{SYSTEM_LINE}.{c}": v for c, v in columns.items()})
            block[SYSTEM_LINE] = summary | {"reference": first.name}
            notes += _line_notes(SYSTEM_LINE, summary, self.required)
        if not solution.ok:
            notes.append(
                "torque margin: the run failed, its margins cover the rows computed "
                "and the check is not passed"
            )
        return dataclasses.replace(solution, channels=channels), block, notes


def _line_torques(
    line: _Line, solution: ml.Solution, restart_friction: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The line's driving, factored resistive and restart resistive sums (N*m, per row)."""
    ch, n = solution.channels, solution.time.size
    driving, resistive, restart = np.zeros(n), np.zeros(n), np.zeros(n)
    for term in line.terms:
        if term.friction:
            torque = -np.abs(ch[term.column])
        else:
            torque = -line.sense * term.scale * ch[term.column]
        driving += np.where(torque > 0.0, torque, 0.0)
        resisting = term.factor * np.where(torque < 0.0, -torque, 0.0)
        resistive += resisting
        if term.kind not in _RATE_KINDS:
            restart += resisting * (restart_friction if term.friction else 1.0)
    return driving, resistive, restart


def _margin(
    driving: np.ndarray,
    resistive: np.ndarray,
    restart: np.ndarray,
    angle: np.ndarray,
    time: np.ndarray,
    required: float,
) -> tuple[dict[str, np.ndarray], dict]:
    """The margin columns (TM_UNITS) and summary of driving and resistive sums."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(resistive > 0.0, driving / resistive, np.nan)
        restart_ratio = np.where(restart > 0.0, driving / restart, np.nan)
    columns = {
        "driving": driving,
        "resistive": resistive,
        "ratio": ratio,
        "restart_ratio": restart_ratio,
        "excess": driving - required * resistive,
        "angle": angle,
    }
    return columns, _line_summary(time, angle, ratio, restart_ratio, required)


def _line_summary(
    time: np.ndarray,
    angle: np.ndarray,
    ratio: np.ndarray,
    restart_ratio: np.ndarray,
    required: float,
) -> dict:
    out: dict = {"undefined_rows": int(np.sum(~np.isfinite(ratio)))}
    for key, values in (("", ratio), ("restart_", restart_ratio)):
        finite = np.isfinite(values)
        if not finite.any():
            out.update(
                {f"{key}min_ratio": None, f"{key}time_of_min": None, f"{key}angle_of_min": None}
            )
            continue
        i = int(np.argmin(np.where(finite, values, np.inf)))
        out.update(
            {
                f"{key}min_ratio": float(values[i]),
                f"{key}time_of_min": float(time[i]),
                f"{key}angle_of_min": float(angle[i]),
            }
        )
    mins = (out["min_ratio"], out["restart_min_ratio"])
    out["passed"] = (
        all(m is not None and m >= required for m in mins) and out["undefined_rows"] == 0
    )
    return out


def _line_notes(name: str, s: dict, required: float) -> list[str]:
    notes = []
    if s["undefined_rows"]:
        notes.append(
            f"torque margin {name}: no resistive torque at {s['undefined_rows']} "
            "row(s): TM undefined there (column ratio empty)"
        )
    for key, what in (("", "TM"), ("restart_", "restart TM")):
        m = s[f"{key}min_ratio"]
        if m is not None and m < required:
            notes.append(
                f"torque margin {name}: {what} {m:.4g} < {required:g} at "
                f"{np.degrees(s[f'{key}angle_of_min']):.4g} deg "
                f"(t = {s[f'{key}time_of_min']:.6g} s): check failed"
            )
    return notes


def plan_torque_margin(cf, built) -> MarginPlan | None:
    """The plan of `cf.case.torque_margin` (None without one); its requests are appended to
    `built.requests`. Raises InputError naming every contributor that cannot be read."""
    tm = cf.case.torque_margin
    if tm is None:
        return None
    problems: list[Diagnostic] = []

    def error(key: str, message: str, hint: str | None = None) -> None:
        file, line, col = cf.where("case", key)
        problems.append(Diagnostic(file, line, col, key, message, hint=hint))

    if isinstance(built.analysis, ml.Modes):
        error(
            "torque_margin",
            "a torque margin needs an analysis along the deployment "
            "(quasi-static, kinematic or dynamic), not modes",
        )
    lines, requests = [], []
    for name, hl in tm.hinge_lines.items():
        key = f"torque_margin.hinge_lines.{name}"
        joint = cf.mechanism.joints.get(hl.joint)
        if joint is None or joint.type not in ("revolute", "cylindrical"):
            error(
                f"{key}.joint",
                f"'{hl.joint}' is not a revolute or cylindrical joint of the mechanism",
            )
            continue
        line = _Line(name, 1.0 if hl.sense == "positive" else -1.0, f"{_HIDDEN}{name}.value")
        requests.append(ml.JointCoordinate(f"{_HIDDEN}{name}", hl.joint, "angle"))
        for label, c in hl.contributors.items():
            term = _term(
                cf, built, name, label, c, hl.joint, f"{key}.contributors.{label}", error, requests
            )
            if term is not None:
                line.terms.append(term)
        if tm.system:
            line.rate_column = f"{_HIDDEN}{name}_rate.value"
            requests.append(ml.JointCoordinate(f"{_HIDDEN}{name}_rate", hl.joint, "omega"))
        lines.append(line)
    if tm.system and SYSTEM_LINE in tm.hinge_lines:
        error(
            f"torque_margin.hinge_lines.{SYSTEM_LINE}",
            f"'{SYSTEM_LINE}' names the system margin's columns: rename this hinge line",
        )
    if tm.system and len(tm.hinge_lines) < 2:
        error("torque_margin.system", "a system margin needs two hinge lines or more")
    if problems:
        raise InputError(problems)
    built.requests.extend(requests)
    return MarginPlan(tm.required, tm.restart_friction, lines, requests, tm.system)


def _term(cf, built, line: str, label: str, c, joint: str, key: str, error, requests):
    factor = c.factor if c.factor is not None else DEFAULT_FACTORS[c.kind]
    hidden = f"{_HIDDEN}{line}_{label}"
    if c.expression is not None:
        tables = {
            n: Table(n, t.x, t.y, t.interpolation, t.extrapolate)
            for n, t in cf.mechanism.tables.items()
        }
        try:
            function = parse(c.expression).compile(cf.parameters, tables)
        except ExpressionError as exc:
            error(f"{key}.expression", str(exc))
            return None
        requests.append(ml.ExpressionOutput(hidden, Guarded(function, key)))
        return _Term(label, c.kind, factor, f"{hidden}.value", False)
    f = cf.mechanism.forces.get(label)
    if f is None or f.type not in _ELEMENT_TYPES or getattr(f, "joint", None) != joint:
        on_joint = [
            n
            for n, g in cf.mechanism.forces.items()
            if g.type in _ELEMENT_TYPES and getattr(g, "joint", None) == joint
        ]
        close = difflib.get_close_matches(label, on_joint, n=1)
        error(
            key,
            f"'{label}' is not a torsion_spring, joint_friction or damper on joint "
            f"'{joint}' (or give an expression)",
            f"did you mean '{close[0]}'?" if close else None,
        )
        return None
    if label not in built.mechanism.forces:
        error(
            key,
            f"'{label}' is not active in this case (effects or loads switch it off): "
            "a torque margin must count every torque of the hinge line",
        )
        return None
    if f.type == "damper":
        # c * omega from the joint's rate: a quasi-static run evaluates elements without
        # velocities, yet its motion imposes the deployment rate the damper resists
        requests.append(ml.JointCoordinate(hidden, joint, "omega"))
        return _Term(label, c.kind, factor, f"{hidden}.value", False, f.damping)
    requests.append(ml.ElementOutput(hidden, label))
    friction = f.type == "joint_friction"
    return _Term(label, c.kind, factor, f"{hidden}.{'capacity' if friction else 'value'}", friction)
