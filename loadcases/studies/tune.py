"""Tune one parameter of a case to a target: the frequency of mode N of a `modes` case
(seed 003 appendix A: the latch-up spring tuned to the first flexible mode of the FE model),
or the torque margin of a hinge line of a case with `torque_margin:` (seed 003 section 2.1:
"the TM analysis settles spring stiffness and wind-up"; `tune_margin`).

The case is loaded with the parameter overridden (as a set's sweep does) and solved for its
modes; the root of f(p) = frequency of mode N - target is bracketed from the case's own
value by doubling and halving, then found by Brent's method (scipy.optimize.brentq) to
`rtol` of the parameter. A margin is the run's minimum TM of the hinge line over its rows
(`min_ratio` of the summary; the restart TM with `restart=True`). Every evaluation is
recorded. The hinge-line constraints of A.2.1 (the hinge line held as in the FE model) are
the case's joints: tune a case that holds them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from scipy.optimize import brentq

from loadcases.build.system_margin import SYSTEM_LINE
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.inputs.loader import load_case
from loadcases.run import run_case

__all__ = ["TuneError", "TuneResult", "tune_margin", "tune_parameter"]

_EXPANSIONS = 40  # doublings / halvings tried for a bracket (a factor 2^40 either way)


class TuneError(RuntimeError):
    """No value of the parameter gives the target (no bracket, or a run failed)."""


@dataclass
class TuneResult:
    """The tuned value (SI) and what it gives (`achieved`: a frequency in Hz, or a torque
    margin); `evaluations` are the (parameter value, achieved) pairs computed, in order.
    `mode` is the tuned mode, `hinge_line` the tuned hinge line (the other is None)."""

    parameter: str
    mode: int | None
    target: float
    value: float
    achieved: float
    evaluations: list[tuple[float, float]] = field(default_factory=list)
    hinge_line: str | None = None

    @property
    def frequency(self) -> float:
        """The frequency (Hz) of the tuned mode (a mode tuning)."""
        return self.achieved

    @property
    def iterations(self) -> int:
        return len(self.evaluations)


def _input_error(cf, key: str, message: str) -> InputError:
    file, line, col = cf.where("case", key) if key else (cf.path, 1, 1)
    return InputError([Diagnostic(file, line, col, key, message)])


def _checked_case(path: Path, parameter: str, mode: int):
    cf = load_case(path)
    if cf.case.analysis.type != "modes":
        raise _input_error(
            cf, "analysis.type", f"tuning needs a modes analysis, not '{cf.case.analysis.type}'"
        )
    _known_parameter(cf, parameter)
    if mode < 1:
        raise _input_error(cf, "analysis", f"mode {mode}: modes are numbered from 1")
    return cf


def _frequency(path: Path, parameter: str, value: float, mode: int) -> float:
    outcome = run_case(load_case(path, overrides={parameter: value}))
    if not outcome.solution.ok:
        raise TuneError(
            f"{parameter} = {value:.10g}: the modes analysis failed: {outcome.solution.message}"
        )
    frequencies = outcome.solution.channels["mode.frequency"]
    if mode > frequencies.size:
        raise InputError(
            [
                Diagnostic(
                    str(path),
                    1,
                    1,
                    "analysis",
                    f"mode {mode}: the case has {frequencies.size} modes",
                )
            ]
        )
    return float(frequencies[mode - 1])


def tune_parameter(
    path: str | Path, *, parameter: str, mode: int, target: float, rtol: float = 1e-12
) -> TuneResult:
    """The value of `parameter` (SI) giving mode `mode` the frequency `target` (Hz).

    Raises InputError for a case that is not a modes analysis, an unknown parameter or a
    mode out of range; TuneError when no bracket is found or a run fails.
    """
    path = Path(path)
    cf = _checked_case(path, parameter, mode)
    result = TuneResult(parameter, mode, target, math.nan, math.nan)
    return _solve(cf, result, lambda value: _frequency(path, parameter, value, mode), rtol=rtol)


def tune_margin(
    path: str | Path,
    *,
    parameter: str,
    hinge_line: str,
    target: float | None = None,
    restart: bool = False,
    rtol: float = 1e-12,
) -> TuneResult:
    """The value of `parameter` (SI: a spring's stiffness, its wind-up angle) for which the
    minimum torque margin of `hinge_line` over the run is `target` (default: the case's
    `required`); the restart TM with `restart`; `hinge_line="system"`: the system margin of
    a case with `torque_margin: {system: true}`.

    Raises InputError for a case without that hinge line in `torque_margin:` or an unknown
    parameter; TuneError when no bracket is found, a run fails or its TM is undefined.
    """
    path = Path(path)
    cf = load_case(path)
    tm = cf.case.torque_margin
    system = tm is not None and tm.system and hinge_line == SYSTEM_LINE
    if tm is None or (hinge_line not in tm.hinge_lines and not system):
        known = (
            ", ".join([*tm.hinge_lines, *([SYSTEM_LINE] if tm.system else [])]) if tm else "none"
        )
        raise _input_error(
            cf,
            "torque_margin" if tm is not None else "",
            f"no hinge line '{hinge_line}' in the case's torque_margin (hinge lines: {known})",
        )
    _known_parameter(cf, parameter)
    goal = tm.required if target is None else target
    result = TuneResult(parameter, None, goal, math.nan, math.nan, hinge_line=hinge_line)
    key = "restart_min_ratio" if restart else "min_ratio"

    def margin(value: float) -> float:
        outcome = run_case(load_case(path, overrides={parameter: value}))
        if not outcome.solution.ok:
            raise TuneError(
                f"{parameter} = {value:.10g}: the run failed: {outcome.solution.message}"
            )
        block = outcome.checks["torque_margin"]
        found = (block[SYSTEM_LINE] if system else block["hinge_lines"][hinge_line])[key]
        if found is None:
            raise TuneError(
                f"{parameter} = {value:.10g}: no resistive torque on {hinge_line} at any "
                "row: its torque margin is undefined"
            )
        return float(found)

    return _solve(cf, result, margin, rtol=rtol, at_least=True)


def _known_parameter(cf, parameter: str) -> None:
    if parameter not in cf.parameters:
        known = ", ".join(sorted(cf.parameters)) or "none"
        raise _input_error(
            cf,
            "parameters",
            f"no parameter '{parameter}' in the case or its mechanism (parameters: {known})",
        )


def _solve(cf, result: TuneResult, evaluate, *, rtol: float, at_least: bool = False) -> TuneResult:
    """`result` completed: the root of evaluate(value) - target, bracketed from the
    parameter's value in the case; with `at_least`, on the side where the target is met
    (a margin of 2 - 4e-10 fails a check of 2)."""
    known: dict[float, float] = {}

    def error(value: float) -> float:
        if value not in known:  # brentq asks again for the ends of the bracket
            known[value] = evaluate(value)
            result.evaluations.append((value, known[value]))
        return known[value] - result.target

    start = cf.parameters[result.parameter]
    if start == 0.0:
        raise _input_error(
            cf,
            "parameters",
            f"'{result.parameter}' is 0: give a non-zero starting "
            "value (the bracket is searched by doubling and halving it)",
        )
    low, high = _bracket(error, start)
    value = (
        low
        if low == high
        else brentq(error, low, high, xtol=abs(start) * 1e-15, rtol=rtol, maxiter=200)
    )
    if at_least and error(value) < 0.0:
        value = _passing(error, value, high if error(high) >= 0.0 else low)
    result.value = value
    result.achieved = result.target + error(value)
    return result


def _passing(error, value: float, passing: float) -> float:
    """The root `value` moved towards the bracket's end `passing` (where the error is >= 0)
    by relative steps from 1e-10, doubled, until the error is >= 0 (at most `passing`)."""
    step = 1e-10 * abs(value) * (1.0 if passing > value else -1.0)
    while error(value) < 0.0:
        value = value + step
        if (passing - value) * step <= 0.0:
            return passing
        step *= 2.0
    return value


def _bracket(error, start: float) -> tuple[float, float]:
    """Values a < b of the parameter around which the error changes sign: from `start`
    towards the side that the sign of the error and its trend point to."""
    e0 = error(start)
    if e0 == 0.0:
        return start, start
    e1 = error(start * 2.0)
    if e1 == 0.0 or (e1 < 0) != (e0 < 0):
        return start, start * 2.0
    rising = (e1 - e0) * start > 0  # frequency grows with |parameter|
    factor = 2.0 if (e0 < 0) == rising else 0.5
    previous, e_prev = (start * 2.0, e1) if factor == 2.0 else (start, e0)
    for _ in range(_EXPANSIONS):
        value = previous * factor
        e = error(value)
        if (e < 0) != (e_prev < 0):
            return min(previous, value), max(previous, value)
        previous, e_prev = value, e
    raise TuneError(
        f"no value of the parameter between {start * 2.0**-_EXPANSIONS:.3g} and "
        f"{start * 2.0**_EXPANSIONS:.3g} gives the target (the frequency stays "
        f"{'above' if e_prev > 0 else 'below'} it)"
    )
