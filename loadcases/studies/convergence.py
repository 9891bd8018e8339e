"""Convergence of a case's results in one parameter (issue 37; seed 003 section 3.2.2,
Table 3-1 and figures 3.2.2-3/4: the number of fixed-interface modes of flexible bodies).

The case is run once per value of the parameter (as `loads run --set NAME=VALUE` would
run it, so the parameter must be defined and of the definition's dimension). Every result
column gives two quantities, its largest and its smallest value over the run (a `modes`
analysis: the frequency of each mode number, as the seed's Tables 3-2/3-3 list them).

A quantity **converges at** the first value of the parameter from which every later value
keeps it within the tolerance: the spread (largest minus smallest) of its values from there
on is at most `tolerance` times its magnitude at the last value. At least two values must
agree, so the last value alone never converges. A quantity at round-off level (below
`NOISE_FLOOR` of its request's largest magnitude over all runs) is marked as such: its
relative changes mean nothing.
"""

from __future__ import annotations

import fnmatch
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.inputs.loader import load_case
from loadcases.inputs.overrides import OverrideError, parse_overrides
from loadcases.report.roundoff import NOISE_FLOOR
from loadcases.results.outcome import RunOutcome
from loadcases.run import run_case

__all__ = [
    "Convergence",
    "Quantity",
    "StudyRun",
    "converged_index",
    "run_study",
]

TIME = "time"
MODE_FREQUENCY = "mode.frequency"


@dataclass(frozen=True)
class Quantity:
    """One quantity against the parameter: `values` (SI, in `unit`; NaN where the run
    failed or lacks it), `converged_at` the index of the value from which it converges
    (None: not converged), `noise`: at round-off level."""

    name: str
    unit: str
    values: tuple[float, ...]
    converged_at: int | None
    noise: bool = False

    def change(self, index: int) -> float:
        """Relative difference of the value at `index` from the last one (NaN if either is
        missing or the last is 0)."""
        last, value = self.values[-1], self.values[index]
        if not (math.isfinite(last) and math.isfinite(value)) or last == 0.0:
            return math.nan
        return (value - last) / abs(last)


@dataclass(frozen=True)
class StudyRun:
    """One run of the study: the parameter's text, its status and cost."""

    text: str
    ok: bool
    message: str
    steps: int
    cpu_seconds: float


@dataclass
class Convergence:
    """The study: the case, the parameter's values (as given and in SI), the tolerance
    (a fraction), the runs and the quantities."""

    case: str
    analysis: str
    parameter: str
    texts: tuple[str, ...]
    values: tuple[float, ...]
    tolerance: float
    runs: list[StudyRun] = field(default_factory=list)
    quantities: list[Quantity] = field(default_factory=list)

    @property
    def failed(self) -> list[StudyRun]:
        return [r for r in self.runs if not r.ok]

    def unconverged(self) -> list[Quantity]:
        """The quantities (round-off left out) that do not converge."""
        return [q for q in self.quantities if q.converged_at is None and not q.noise]


def converged_index(values: Sequence[float], tolerance: float, floor: float = 0.0) -> int | None:
    """The first index from which the spread of the values to the end is at most
    `tolerance` x max(|last value|, `floor`); None when only the last value is left (or a
    value from there on is not finite)."""
    scale = max(abs(values[-1]), floor) if values else 0.0
    for start in range(len(values) - 1):
        tail = np.asarray(values[start:], dtype=float)
        if np.all(np.isfinite(tail)) and np.ptp(tail) <= tolerance * scale:
            return start
    return None


def _study_error(path: Path, message: str) -> InputError:
    return InputError([Diagnostic(str(path), 1, 1, "", message)])


def _checked_values(path: Path, values: Sequence[float]) -> None:
    if len(values) < 2:
        raise _study_error(path, "a convergence study needs at least two values")
    if any(b <= a for a, b in itertools.pairwise(values)):
        raise _study_error(
            path,
            "the values must increase (the study asks from which value on the results stay "
            "within the tolerance)",
        )


def run_study(
    path: str | Path,
    *,
    parameter: str,
    texts: Sequence[str],
    tolerance: float,
    columns: Sequence[str] = (),
    progress=None,
) -> Convergence:
    """Run the case at each value of `parameter` (texts as on the command line, `"4"`,
    `"200 Hz"`) and judge every quantity's convergence to `tolerance` (a fraction).

    Raises InputError for an unknown parameter, a value of another dimension, values that
    do not increase or a case that is invalid at one of the values; a failed run is kept
    (its quantities NaN), `Convergence.failed` lists it. `progress(text, outcome)` is
    called after each run. `columns`: glob patterns of the result columns studied (a
    modes analysis: of `mode K`); none: all. A pattern that matches nothing is an
    InputError, raised after the first run.
    """
    path = Path(path)
    try:
        overrides = [parse_overrides([f"{parameter}={text}"])[0] for text in texts]
    except OverrideError as error:
        raise _study_error(path, str(error)) from None
    _checked_values(path, [o.value for o in overrides])
    if not tolerance > 0.0:
        raise _study_error(path, f"tolerance {tolerance:g}: must be positive")
    outcomes: list[RunOutcome] = []
    for override in overrides:
        outcome = run_case(load_case(path, what_if=(override,)))
        outcomes.append(outcome)
        if len(outcomes) == 1:
            _check_patterns(path, columns, _names(outcome))
        if progress is not None:
            progress(override.text, outcome)
    first = outcomes[0]
    study = Convergence(
        case=first.name.split("[", 1)[0],
        analysis=first.analysis,
        parameter=parameter,
        texts=tuple(o.text for o in overrides),
        values=tuple(o.value for o in overrides),
        tolerance=tolerance,
    )
    for text, outcome in zip(study.texts, outcomes):
        s = outcome.solution
        study.runs.append(
            StudyRun(text, s.ok, s.message, s.stats.steps, float(s.stats.cpu_seconds))
        )
    solved = [o if o.solution.ok else None for o in outcomes]
    if study.analysis == "modes":
        study.quantities = _mode_quantities(solved, tolerance)
    else:
        study.quantities = _peak_quantities(solved, tolerance)
    if columns:
        study.quantities = [
            q
            for q in study.quantities
            if _matches(q.name.removesuffix(" max").removesuffix(" min"), columns)
        ]
    return study


def _names(outcome: RunOutcome) -> list[str]:
    """The names `columns` patterns match in a run: its result columns, or `mode K`."""
    channels = outcome.solution.channels
    if outcome.analysis == "modes":
        return [f"mode {k + 1}" for k in range(np.asarray(channels.get(MODE_FREQUENCY, ())).size)]
    return [c for c in channels if c != TIME]


def _base(name: str) -> str:
    """The column of a quantity's name (`COLUMN max` -> `COLUMN`; `mode K` as it is)."""
    return name.removesuffix(" max").removesuffix(" min")


def _matches(name: str, patterns: Sequence[str]) -> bool:
    return any(fnmatch.fnmatchcase(name, p) for p in patterns)


def _check_patterns(path: Path, patterns: Sequence[str], names: list[str]) -> None:
    for pattern in patterns:
        if not any(fnmatch.fnmatchcase(n, pattern) for n in names):
            shown = ", ".join(names[:12]) + (", ..." if len(names) > 12 else "")
            raise _study_error(path, f"columns '{pattern}': matches no result ({shown})")


def _mode_quantities(outcomes: list[RunOutcome | None], tolerance: float) -> list[Quantity]:
    """The frequency of each mode number (Hz) against the parameter."""
    frequencies = [
        np.asarray(o.solution.channels[MODE_FREQUENCY]) if o is not None else np.zeros(0)
        for o in outcomes
    ]
    count = max((f.size for f in frequencies), default=0)
    quantities = []
    for k in range(count):
        values = tuple(float(f[k]) if k < f.size else math.nan for f in frequencies)
        verdict = converged_index(values, tolerance)
        quantities.append(Quantity(f"mode {k + 1}", "Hz", values, verdict))
    return quantities


def _peak_quantities(outcomes: list[RunOutcome | None], tolerance: float) -> list[Quantity]:
    """The largest and smallest value of every result column against the parameter."""
    columns: dict[str, str] = {}
    for o in outcomes:
        if o is not None:
            columns |= {c: o.column_units.get(c, "") for c in o.solution.channels if c != TIME}
    peaks: dict[str, list[tuple[float, float]]] = {c: [] for c in columns}
    for o in outcomes:
        for column in columns:
            history = o.solution.channels.get(column, ()) if o is not None else ()
            finite = np.asarray(history, dtype=float)
            finite = finite[np.isfinite(finite)]
            peaks[column].append(
                (float(finite.max()), float(finite.min())) if finite.size else (math.nan,) * 2
            )
    largest: dict[str, float] = {}
    for column, pairs in peaks.items():
        request = column.split(".", 1)[0]
        size = max((abs(v) for pair in pairs for v in pair if math.isfinite(v)), default=0.0)
        largest[request] = max(largest.get(request, 0.0), size)
    quantities = []
    for column, pairs in peaks.items():
        floor = NOISE_FLOOR * largest[column.split(".", 1)[0]]
        for side, index in (("max", 0), ("min", 1)):
            values = tuple(pair[index] for pair in pairs)
            size = max((abs(v) for v in values if math.isfinite(v)), default=0.0)
            quantities.append(
                Quantity(
                    f"{column} {side}",
                    columns[column],
                    values,
                    converged_index(values, tolerance, floor),
                    noise=size <= floor,
                )
            )
    return quantities
