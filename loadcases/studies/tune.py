"""Tune one parameter of a `modes` case so that mode N hits a target frequency (seed 003
appendix A: the latch-up spring tuned to the first flexible mode of the FE model).

The case is loaded with the parameter overridden (as a set's sweep does) and solved for its
modes; the root of f(p) = frequency of mode N - target is bracketed from the case's own
value by doubling and halving, then found by Brent's method (scipy.optimize.brentq) to
`rtol` of the parameter. Every evaluation is recorded. The hinge-line constraints of A.2.1
(the hinge line held as in the FE model) are the case's joints: tune a case that holds them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from scipy.optimize import brentq

from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.inputs.loader import load_case
from loadcases.run import run_case

__all__ = ["TuneError", "TuneResult", "tune_parameter"]

_EXPANSIONS = 40  # doublings / halvings tried for a bracket (a factor 2^40 either way)


class TuneError(RuntimeError):
    """No value of the parameter gives the target (no bracket, or a run failed)."""


@dataclass
class TuneResult:
    """The tuned value (SI) and the frequency (Hz) it gives; `evaluations` are the
    (parameter value, frequency) pairs computed, in order."""

    parameter: str
    mode: int
    target: float
    value: float
    frequency: float
    evaluations: list[tuple[float, float]] = field(default_factory=list)

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
    if parameter not in cf.parameters:
        known = ", ".join(sorted(cf.parameters)) or "none"
        raise _input_error(
            cf,
            "parameters",
            f"no parameter '{parameter}' in the case or its mechanism (parameters: {known})",
        )
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

    known: dict[float, float] = {}

    def error(value: float) -> float:
        if value not in known:  # brentq asks again for the ends of the bracket
            known[value] = _frequency(path, parameter, value, mode)
            result.evaluations.append((value, known[value]))
        return known[value] - target

    start = cf.parameters[parameter]
    if start == 0.0:
        raise _input_error(
            cf,
            "parameters",
            f"'{parameter}' is 0: give a non-zero starting "
            "value (the bracket is searched by doubling and halving it)",
        )
    low, high = _bracket(error, start)
    value = (
        low
        if low == high
        else brentq(error, low, high, xtol=abs(start) * 1e-15, rtol=rtol, maxiter=200)
    )
    result.value = value
    result.frequency = target + error(value)
    return result


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
