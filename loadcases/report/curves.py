"""Envelope curves: the upper and lower envelope of each column over an abscissa, per family.

A family is the runs of one case file (one case name) across the set's sweeps. Its
abscissa is `abscissa.value` (the case's `abscissa:` expression, recorded by a set run)
when every run of the family has it, else `time`; the curve names it by its expression
(`angle(trunnion)`) when the caller knows it.

The common grid is the sorted union of the abscissa values of all the family's runs
(thinned to `MAX_GRID_POINTS` evenly spaced points over the same range when larger). Each
run is interpolated linearly onto the grid points inside its own range, segment by segment
between consecutive output rows, so an abscissa that goes back and forth (a swinging
pendulum's angle) contributes every branch; outside a run's range it contributes nothing.
At each grid point the upper (lower) envelope is the max (min) over the runs covering it;
points covered by no run are NaN. Rows with a NaN abscissa or value are skipped.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from loadcases.build.requests import ABSCISSA_COLUMN
from loadcases.results.files import TIME_COLUMN
from loadcases.results.saved import SavedRun

__all__ = [
    "ASKED_ONLY",
    "LOAD_KINDS",
    "MAIN_COLUMNS",
    "MAX_GRID_POINTS",
    "EnvelopeCurve",
    "envelope_curves",
    "envelope_on_grid",
    "main_columns",
    "plot_curves",
]

MAX_GRID_POINTS = 20_000  # more would only slow the workbook charts down
MAIN_COLUMNS = 4  # columns charted and plotted per family
LOAD_UNITS = frozenset({"N", "N*m"})
# Request kinds (`loadcases.build.requests.request_kinds`) whose force and torque columns
# are loads a sizing report charts (an expression in N or N*m is a load the case defines:
# the door's handle force); friction and energy are charted only when asked.
LOAD_KINDS = frozenset({"reaction", "effort", "element", "contact", "expression"})
ASKED_ONLY = frozenset({"friction", "energy"})


@dataclass
class EnvelopeCurve:
    """Upper/lower envelopes of one family: `x` (m,) on `abscissa`; {column: (m,)} in SI."""

    family: str
    abscissa: str
    abscissa_unit: str
    x: np.ndarray
    upper: dict[str, np.ndarray] = field(default_factory=dict)
    lower: dict[str, np.ndarray] = field(default_factory=dict)
    runs: tuple[str, ...] = ()
    units: dict[str, str] = field(default_factory=dict)
    kinds: dict[str, str] = field(default_factory=dict)  # {request: kind} of the runs
    charted: tuple[str, ...] = ()  # the columns charted, chosen in SI (`main_columns`)


def _grid(xs: list[np.ndarray]) -> np.ndarray:
    values = np.concatenate([x[np.isfinite(x)] for x in xs]) if xs else np.empty(0)
    grid = np.unique(values)
    if grid.size > MAX_GRID_POINTS:
        grid = np.linspace(grid[0], grid[-1], MAX_GRID_POINTS)
    return grid


def _accumulate(
    grid: np.ndarray, x: np.ndarray, ys: np.ndarray, upper: np.ndarray, lower: np.ndarray
) -> None:
    """Fold one run into upper/lower (columns, grid points) on `grid`: its abscissa x (n,)
    and its columns ys (n, columns), segment by segment between rows. A column with one
    finite row (or a run of one row: a static analysis) contributes that point alone."""
    ys = np.where(np.isfinite(ys), ys, np.nan)  # an infinite value is no value either
    rows = np.isfinite(x)
    finite = rows[:, None] & ~np.isnan(ys)
    points = range(ys.shape[1]) if x.size == 1 else np.flatnonzero(finite.sum(axis=0) == 1)
    for column in points:
        keep = np.flatnonzero(finite[:, column])
        at = np.searchsorted(grid, x[keep])
        hit = (at < grid.size) & (grid[np.minimum(at, grid.size - 1)] == x[keep])
        np.fmax.at(upper[column], at[hit], ys[keep[hit], column])
        np.fmin.at(lower[column], at[hit], ys[keep[hit], column])
    if x.size == 1:
        return
    # the grid points inside each segment between two rows of finite abscissa, found once
    # for all columns; a segment with a NaN end gives NaN, which fmax and fmin pass over
    seg = np.flatnonzero(rows[:-1] & rows[1:])
    x0, x1 = x[seg], x[seg + 1]
    first = np.searchsorted(grid, np.minimum(x0, x1), side="left")
    last = np.searchsorted(grid, np.maximum(x0, x1), side="right")
    counts = np.maximum(last - first, 0)
    owner = np.repeat(np.arange(seg.size), counts)
    index = first[owner] + (np.arange(owner.size) - np.repeat(np.cumsum(counts) - counts, counts))
    dx = (x1 - x0)[owner]
    s = np.divide(grid[index] - x0[owner], dx, out=np.zeros(owner.size), where=dx != 0.0)
    flat = dx == 0.0
    ends = seg[owner]
    for column in range(ys.shape[1]):
        ya, yb = ys[ends, column], ys[ends + 1, column]
        values = ya + s * (yb - ya)
        np.fmax.at(upper[column], index, np.where(flat, np.maximum(ya, yb), values))
        np.fmin.at(lower[column], index, np.where(flat, np.minimum(ya, yb), values))


def envelope_on_grid(
    pairs: Iterable[tuple[np.ndarray, np.ndarray]], grid: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(upper, lower) on `grid` (sorted) of curves `(x, y)`; NaN where no curve covers."""
    upper = np.full((1, grid.size), -np.inf)
    lower = np.full((1, grid.size), np.inf)
    for x, y in pairs:
        y = np.asarray(y, dtype=float)
        _accumulate(grid, np.asarray(x, dtype=float), y.reshape(-1, 1), upper, lower)
    return _uncovered_nan(upper[0]), _uncovered_nan(lower[0])


def _uncovered_nan(values: np.ndarray) -> np.ndarray:
    """The envelope with the grid points no run covers (still +-inf) set to NaN."""
    values[~np.isfinite(values)] = np.nan
    return values


def _family_curve(
    family: str,
    runs: list[SavedRun],
    expression: str | None,
    skip: Collection[str],
    asked: Sequence[str] = (),
) -> EnvelopeCurve:
    use_abscissa = all(ABSCISSA_COLUMN in run.channels for run in runs)
    name = ABSCISSA_COLUMN if use_abscissa else TIME_COLUMN
    xs = [run.channels[name] if use_abscissa else run.time for run in runs]
    units = {k: v for run in runs for k, v in run.units.items()}
    grid = _grid(xs)
    curve = EnvelopeCurve(
        family,
        (expression or name) if use_abscissa else name,
        units.get(name, "s" if name == TIME_COLUMN else ""),
        grid,
        runs=tuple(run.name for run in runs),
        units=units,
        kinds={k: v for run in runs for k, v in run.kinds.items()},
    )
    columns = list(
        dict.fromkeys(
            c for run in runs for c in run.channels if c != ABSCISSA_COLUMN and c not in skip
        )
    )
    place = {column: n for n, column in enumerate(columns)}
    upper = np.full((len(columns), grid.size), -np.inf)
    lower = np.full((len(columns), grid.size), np.inf)
    for x, run in zip(xs, runs):
        have = [place[c] for c in run.channels if c in place]
        ys = np.column_stack([run.channels[columns[n]] for n in have]) if have else None
        if ys is not None:
            x = np.asarray(x, dtype=float)
            ys = ys.astype(float, copy=False)
            if have == list(range(len(columns))):
                _accumulate(grid, x, ys, upper, lower)
            else:  # a run without some of the family's columns: its own rows of the sums
                sub_upper, sub_lower = upper[have], lower[have]
                _accumulate(grid, x, ys, sub_upper, sub_lower)
                upper[have], lower[have] = sub_upper, sub_lower
    for n, column in enumerate(columns):
        curve.upper[column] = _uncovered_nan(upper[n])
        curve.lower[column] = _uncovered_nan(lower[n])
    curve.charted = tuple(_chosen(curve, asked))
    return curve


def envelope_curves(
    runs: Iterable[SavedRun],
    abscissae: Mapping[str, str] | None = None,
    skip: Collection[str] = (),
    asked: Sequence[str] = (),
) -> list[EnvelopeCurve]:
    """One curve set per family, families in first-seen order (give only `ok` runs);
    a family whose runs cover a single abscissa value (static runs) has none. A family's
    abscissa is named by its expression from `abscissae` {family: text} when given;
    columns in `skip` (numerical noise) get no curve; `asked` (`report.charts`) are
    charted besides the main columns."""
    families: dict[str, list[SavedRun]] = {}
    for run in runs:
        families.setdefault(run.family, []).append(run)
    names = abscissae or {}
    curves = [
        _family_curve(f, members, names.get(f), skip, asked) for f, members in families.items()
    ]
    return [curve for curve in curves if curve.x.size >= 2]  # one point is no curve


def _peak(curve: EnvelopeCurve, column: str) -> float:
    """The largest finite |envelope| value of a column (-1 when it has none)."""
    values = np.concatenate([curve.upper[column], curve.lower[column]])
    finite = np.abs(values[np.isfinite(values)])
    return float(finite.max()) if finite.size else -1.0


def _is_load(curve: EnvelopeCurve, column: str) -> bool:
    """A column in N or N*m (SI) of a load request (of any request in runs saved without
    kinds)."""
    kind = curve.kinds.get(column.rsplit(".", 1)[0])
    return curve.units.get(column) in LOAD_UNITS and (kind is None or kind in LOAD_KINDS)


def _largest(curve: EnvelopeCurve, columns: list[str]) -> list[str]:
    """Each request's column of largest peak (of each unit: a joint's force and moment),
    ranked by its peak relative to the largest of its unit (N against N, N*m against N*m:
    100 kN and 2 kN*m both rank first)."""
    peaks = {c: _peak(curve, c) for c in columns}
    best: dict[tuple[str, str], str] = {}
    for column in columns:
        key = (column.rsplit(".", 1)[0], curve.units.get(column) or "")
        if key not in best or peaks[column] > peaks[best[key]]:
            best[key] = column
    top: dict[str, float] = {}
    for column in best.values():
        unit = curve.units.get(column) or ""
        top[unit] = max(top.get(unit, 0.0), peaks[column])

    def score(column: str) -> tuple[float, float]:
        largest = top[curve.units.get(column) or ""]
        return (peaks[column] / largest if largest > 0 else 0.0), peaks[column]

    return sorted(best.values(), key=score, reverse=True)


def _chosen(curve: EnvelopeCurve, asked: Sequence[str]) -> list[str]:
    """The `MAIN_COLUMNS` largest loads (columns in N or N*m of joint reactions, motion
    efforts, force elements, contacts and expressions: `LOAD_KINDS`), one per request and
    unit (`_largest`); with no load, the largest other columns but `ASKED_ONLY`; then
    the columns `asked` (`report.charts`: a request's every column, or one column)."""
    columns = list(curve.upper)
    loads = [c for c in columns if _is_load(curve, c)]
    if not loads:
        loads = [c for c in columns if curve.kinds.get(c.rsplit(".", 1)[0]) not in ASKED_ONLY]
    chosen = _largest(curve, loads)[:MAIN_COLUMNS]
    chosen += [c for c in columns if c in asked or c.rsplit(".", 1)[0] in asked]
    return list(dict.fromkeys(chosen))


def main_columns(curve: EnvelopeCurve) -> list[str]:
    """The columns charted and plotted for a family: those chosen when its curves were
    made in SI (`envelope_curves`), else chosen now (`_chosen`, units read as SI)."""
    return list(curve.charted) if curve.charted else _chosen(curve, ())


def plot_curves(curves: Iterable[EnvelopeCurve]) -> list[dict[str, object]]:
    """One mapping per main column of each family, as `loadcases.report.plots` draws them:
    family, column, unit, abscissa_name, abscissa_unit, x, upper, lower."""
    return [
        {
            "family": c.family,
            "column": column,
            "unit": c.units.get(column, ""),
            "abscissa_name": c.abscissa,
            "abscissa_unit": c.abscissa_unit,
            "x": c.x,
            "upper": c.upper[column],
            "lower": c.lower[column],
        }
        for c in curves
        for column in main_columns(c)
    ]
