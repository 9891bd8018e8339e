"""The case's analysis settings as a mechlib analysis, and its initial values."""

from __future__ import annotations

from typing import Any

import mechlib as ml
from loadcases.build.context import Builder
from loadcases.checks.phases import phase_name

__all__ = ["branch_check", "build_analysis", "initial_values"]


def build_analysis(b: Builder):
    """The mechlib analysis of the case (`mechlib.Phases` for `phases:`), or None after an
    error at its key."""
    if b.case.phases:
        return _phases(b)
    return _analysis(b, b.case.analysis, "analysis")


def _phases(b: Builder):
    """The case's phases, each starting at the time the one before it ends (s)."""
    phases, start = [], 0.0
    for index, phase in enumerate(b.case.phases or []):
        analysis = _analysis(b, phase.analysis, f"phases[{index}].analysis", start)
        if analysis is None:
            return None
        name = phase_name(b.case, index)
        motions = None if phase.motions is None else tuple(phase.motions)
        phases.append(ml.Phase(analysis, name, tuple(phase.locks), motions))
        start = getattr(analysis, "end", start)
    return ml.Phases(tuple(phases))


def _analysis(b: Builder, a, key: str, start: float = 0.0):
    """One mechlib analysis from its settings at `key`, starting at `start` (s)."""
    if a.type == "modes":
        return ml.Modes(time=0.0)
    if a.type == "static":
        return ml.Static(time=start)
    if a.end is None or a.step is None or a.step <= 0.0 or a.end <= start:
        b.error("case", key, f"a {a.type} analysis needs 'end' and 'step' > 0 (seconds)")
        return None
    limit: dict[str, Any] = {"max_steps": a.max_steps} if a.max_steps is not None else {}
    if start:
        limit["start"] = start
    if a.type == "kinematic":
        return ml.Kinematic(end=a.end, step=a.step, **limit)
    if a.type == "quasi-static":
        return ml.QuasiStatic(end=a.end, step=a.step, **limit)
    integrator = a.integrator or "generalized-alpha"
    if integrator not in ("generalized-alpha", "radau"):
        b.error(
            "case",
            f"{key}.integrator",
            f"unknown integrator '{integrator}': use generalized-alpha or radau",
        )
    options = {
        option: value
        for option, value in (("tolerance", a.tolerance), ("rho_inf", a.rho_inf))
        if value is not None
    }
    if a.output != "steps":  # dense by default: the steps do not depend on the output
        options["dense"] = True
    return ml.Dynamic(
        end=a.end, step=a.step, integrator=integrator, max_step=a.max_step, **options, **limit
    )


def initial_values(b: Builder, mechanism: ml.Mechanism) -> list:
    """The case's initial joint values, body velocities and modal coordinates (a flexible
    body's `modes`/`rates`, one per mode as built; left out with the body's flexibility)."""
    out: list[ml.InitialValue | ml.InitialBodyVelocity | ml.InitialModes] = []
    for name, v in b.case.initial.items():
        if name in b.mech.joints:
            out.append(ml.InitialValue(name, v.value, v.rate, guess=v.guess))
            continue
        if v.omega is not None or v.velocity is not None:
            out.append(ml.InitialBodyVelocity(name, v.omega, v.velocity))
        flexible = mechanism.flexible.get(name)
        modal = v.modes is not None or v.rates is not None or v.deformed is not None
        if flexible is not None and modal and _mode_counts(b, name, v, flexible.component.count):
            out.append(ml.InitialModes(name, v.modes, v.rates, static=v.deformed == "static"))
    return out


def _mode_counts(b: Builder, name: str, v, count: int) -> bool:
    """True when `modes` and `rates` give one value per mode; else an error at each."""
    fits = True
    for key, unit in (("modes", "kg^0.5*m"), ("rates", "kg^0.5*m/s")):
        values = getattr(v, key)
        if values is not None and len(values) != count:
            b.error(
                "case",
                f"initial.{name}.{key}",
                f"{len(values)} values given: body '{name}' has {count} modes as built "
                f"(one value per mode, {unit}; the `modes` request lists them as q1..q{count})",
            )
            fits = False
    return fits


def branch_check(b: Builder) -> ml.BranchCheck:
    """The case's `branches:` settings."""
    branches = b.case.branches
    return ml.BranchCheck(angle=branches.angle, error=branches.on_change == "error")
