"""PNG plots of result columns (vs time or vs another column) and of envelope curves.

One PNG per request: with one run, the request's components are lines grouped in one panel
per unit (`fx fy fz f` in N, `tx ty tz t` in N*m); with several runs, one panel per
component and one line per run (legend = run name). Values are plotted as given: SI, as in
the CSV files, or converted by the caller to report units (`loads plot --units`); axis
labels carry the unit (from the run's `units` map in `NAME.summary.json`, else guessed from
the column name, see `column_unit`). Matplotlib's Agg canvas is used
directly (no pyplot, no global backend switch), and every file is written atomically.

Figure size: `FIG_WIDTH_IN` x `figure_height_in(panels)` inches at `DPI`, i.e. 1000 px
wide and 100 * (1.6 + 2.4 * panels) px high (at least 400 px).
"""

from __future__ import annotations

import fnmatch
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import matplotlib as mpl
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.ticker import AutoMinorLocator

from loadcases.foundation.atomic import atomic_path
from loadcases.foundation.clip import plain_text_plots
from loadcases.results import saved
from loadcases.results.files import SUMMARY_SUFFIX, TIME_COLUMN
from loadcases.results.saved import SavedRun

__all__ = [
    "DPI",
    "FIG_WIDTH_IN",
    "SavedRun",
    "column_unit",
    "figure_height_in",
    "find_result_csvs",
    "load_saved_run",
    "plot_file_name",
    "plot_runs",
    "request_of",
    "select_columns",
    "write_envelope_plots",
]

Run = tuple[str, np.ndarray, dict[str, np.ndarray]]

FIG_WIDTH_IN = 10.0  # inches
DPI = 100  # pixels per inch
# zlib level 1 instead of PIL's 6: a plot's PNG encodes in 6 ms instead of 19 (a set draws
# one per family and main column: the door set's 84), the file about 25 % larger, lossless
PNG_OPTIONS = {"compress_level": 1}
PANEL_HEIGHT_IN = 2.4  # inches per panel
TITLE_HEIGHT_IN = 1.6  # inches for the title and the x label
MIN_HEIGHT_IN = 4.0  # inches
LEGEND_ROWS = 24  # legend entries per legend column
ZERO_FLOOR = 1e-9  # SI; a panel whose values all stay below it shows -1..1, not noise

# Units of components whatever the request (SPEC 1.3).
_COMPONENT_UNITS = {
    "fx": "N",
    "fy": "N",
    "fz": "N",
    "f": "N",
    "normal": "N",
    "friction": "N",
    "tx": "N*m",
    "ty": "N*m",
    "tz": "N*m",
    "t": "N*m",
}
# Words in a request name that tell the unit of its `value` / `x y z` (first match wins).
_NAME_UNITS = (
    ("alpha", "rad/s^2"),
    ("omega", "rad/s"),
    ("rate", "rad/s"),
    ("angle", "rad"),
    ("rotation", "rad"),
    ("torque", "N*m"),
    ("moment", "N*m"),
    ("acc", "m/s^2"),
    ("vel", "m/s"),
    ("speed", "m/s"),
    ("force", "N"),
    ("load", "N"),
    ("tension", "N"),
    ("pos", "m"),
    ("travel", "m"),
    ("stroke", "m"),
    ("length", "m"),
    ("penetration", "m"),
)


def load_saved_run(path: Path) -> SavedRun:
    """Read `NAME.csv` (or the CSV its `NAME.summary.json` names) with the summary's name,
    units and status. Raises ValueError if the CSV is missing."""
    path = Path(path)
    if path.name.endswith(SUMMARY_SUFFIX):
        path = path.with_name(path.name[: -len(SUMMARY_SUFFIX)] + ".csv")
    if not path.is_file():
        raise ValueError(f"{path}: no such results file")
    return saved.load_saved_run(path)


def find_result_csvs(paths: Iterable[Path]) -> list[Path]:
    """Result CSVs named by `paths`: files as given (a summary names its CSV), folders
    searched recursively for `NAME.csv` files next to a `NAME.summary.json`; sorted per
    folder, duplicates once."""
    found: list[Path] = []
    for path in map(Path, paths):
        if path.is_dir():
            found += sorted(
                p
                for p in path.rglob("*.csv")
                if p.with_name(p.name[:-4] + SUMMARY_SUFFIX).is_file()
            )
        else:
            found.append(path)
    return list(dict.fromkeys(found))


def request_of(column: str) -> str:
    """The request name of a `REQUEST.COMPONENT` column (the column itself if no dot)."""
    return column.rsplit(".", 1)[0] if "." in column else column


def select_columns(available: Sequence[str], patterns: Sequence[str] | None) -> list[str]:
    """Columns matching any pattern (fnmatch), in `available` order; none given: all.

    A pattern without a dot or wildcard names a request (all its components): `hinge_force`
    is `hinge_force.*`. Raises ValueError naming the patterns that match nothing.
    """
    if not patterns:
        return list(available)
    globs = [p if ("." in p or any(c in p for c in "*?[")) else p + ".*" for p in patterns]
    unmatched = [p for p, g in zip(patterns, globs) if not fnmatch.filter(available, g)]
    if unmatched:
        requests = ", ".join(dict.fromkeys(request_of(c) for c in available))
        raise ValueError(f"no column matches {', '.join(unmatched)} (requests: {requests})")
    return [c for c in available if any(fnmatch.fnmatchcase(c, g) for g in globs)]


def column_unit(column: str, units: Mapping[str, str] | None = None) -> str:
    """SI unit text of a column: from `units` when there, else from the component name
    (`fx` N, `tx` N*m) or words of the request name (`..angle..` rad); '' if unknown."""
    if units and units.get(column) is not None:
        return str(units[column])
    if column == TIME_COLUMN:
        return "s"
    request, _, component = column.rpartition(".") if "." in column else (column, "", "")
    if component in _COMPONENT_UNITS:
        return _COMPONENT_UNITS[component]
    lowered = request.lower()
    return next((unit for word, unit in _NAME_UNITS if word in lowered), "")


def _label(name: str, unit: str) -> str:
    return f"{name} [{unit}]" if unit else name


def figure_height_in(panels: int) -> float:
    """Figure height (inches) for a number of stacked panels."""
    return max(MIN_HEIGHT_IN, TITLE_HEIGHT_IN + PANEL_HEIGHT_IN * panels)


def plot_file_name(stem: str) -> str:
    """A safe PNG file name: characters other than letters, digits, `_ . - = ,` become `_`."""
    return re.sub(r"[^A-Za-z0-9_.=,-]+", "_", stem).strip("_") + ".png"


def _all_below(panel: _Panel, floor: float) -> bool:
    """True if every finite value of the panel's lines is within +-floor."""
    peaks = [np.nanmax(np.abs(y)) for _, _, y in panel.lines if np.isfinite(y).any()]
    return bool(peaks) and max(peaks) <= floor


@dataclass
class _Panel:
    ylabel: str
    lines: list[tuple[str, np.ndarray, np.ndarray]] = field(default_factory=list)


def _style(ax: Any) -> _MinorGrid:
    """Major and minor grids and the zero line of a panel; returns the minor grid, to be
    updated once the panel's limits are final."""
    ax.grid(True, which="major", alpha=0.5)
    ax.axhline(0.0, color="0.3", linewidth=0.6)
    return _MinorGrid(ax)


class _MinorGrid:
    """A panel's minor grid lines (matplotlib's automatic minor steps between the major
    ticks) as two line collections, one draw call each. matplotlib's own minor grid draws
    three lines per minor tick (two tick marks and the grid line), about half of an
    envelope plot's time; here the minor steps have grid lines but no tick marks."""

    def __init__(self, ax: Any) -> None:
        self.ax = ax
        style = {
            "colors": mpl.rcParams["grid.color"],
            "linewidths": mpl.rcParams["grid.linewidth"],
            "alpha": 0.15,
            "zorder": 1.5,  # with matplotlib's grid lines: under the curves
        }
        self.vertical = LineCollection([], transform=ax.get_xaxis_transform(), **style)
        self.horizontal = LineCollection([], transform=ax.get_yaxis_transform(), **style)
        ax.add_collection(self.vertical, autolim=False)
        ax.add_collection(self.horizontal, autolim=False)

    def update(self) -> None:
        """The lines at the minor steps of the panel's current limits."""
        xs, ys = _minor_steps(self.ax.xaxis), _minor_steps(self.ax.yaxis)
        self.vertical.set_segments([[(x, 0.0), (x, 1.0)] for x in xs])
        self.horizontal.set_segments([[(0.0, y), (1.0, y)] for y in ys])


def _minor_steps(axis: Any) -> list[float]:
    """The minor tick positions matplotlib would draw on `axis` (AutoMinorLocator), inside
    its view and off its major ticks."""
    locator = AutoMinorLocator()
    locator.set_axis(axis)
    low, high = sorted(axis.get_view_interval())
    majors = np.asarray(axis.get_majorticklocs(), dtype=float)
    tolerance = 1e-9 * max(abs(high - low), 1e-300)
    return [
        float(v)
        for v in locator()
        if low <= v <= high and not np.any(np.abs(majors - v) <= tolerance)
    ]


@plain_text_plots()  # `$` in a name is a dollar sign
def _draw(
    panels: list[_Panel],
    *,
    title: str,
    xlabel: str,
    target: Path,
    legend_per_panel: bool = False,
) -> Path:
    """Draw stacked panels sharing x, legends outside on the right (one per panel, or one
    for the figure when every panel has the same lines); save `target` atomically."""
    fig = Figure(
        figsize=(FIG_WIDTH_IN, figure_height_in(len(panels))), dpi=DPI, layout="constrained"
    )
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    labels_seen: dict[str, Any] = {}
    grids = []
    for ax, panel in zip(axes, panels):
        for label, x, y in panel.lines:
            (line,) = ax.plot(x, y, linewidth=1.2, label=label)
            labels_seen.setdefault(label, line)
        ax.set_ylabel(panel.ylabel)
        grids.append(_style(ax))
        if _all_below(panel, ZERO_FLOOR):
            ax.set_ylim(-1.0, 1.0)
        if legend_per_panel:
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
    axes[-1].set_xlabel(xlabel)
    fig.suptitle(title)
    if labels_seen and not legend_per_panel:
        ncols = 1 + (len(labels_seen) - 1) // LEGEND_ROWS
        fig.legend(
            list(labels_seen.values()),
            list(labels_seen),
            loc="outside right upper",
            fontsize="small",
            ncols=ncols,
        )
    for grid in grids:
        grid.update()
    with atomic_path(target) as tmp:
        fig.savefig(tmp, format="png", dpi=DPI, pil_kwargs=PNG_OPTIONS)
    return target


def _request_panels(
    request: str, columns: list[str], runs: list[Run], x: str, units: Mapping[str, str]
) -> list[_Panel]:
    """Panels of one request: by unit for a single run, by component for several."""
    panels: dict[str, _Panel] = {}
    for column in columns:
        unit = column_unit(column, units)
        component = column[len(request) + 1 :] or column
        for run_name, time, channels in runs:
            if column not in channels:
                continue
            xs = time if x == TIME_COLUMN else channels.get(x)
            if xs is None:
                continue
            if len(runs) == 1:
                key, label = unit, component
                ylabel = _label(request, unit)
            else:
                key, label, ylabel = column, run_name, _label(column, unit)
            panels.setdefault(key, _Panel(ylabel)).lines.append((label, xs, channels[column]))
    return list(panels.values())


def plot_runs(
    runs: list[Run],
    columns: Sequence[str] | None = None,
    *,
    x: str = TIME_COLUMN,
    units: Mapping[str, str] | None = None,
    out_dir: Path,
) -> list[Path]:
    """Write one PNG per request of `runs` into `out_dir`; return the paths written.

    runs: `(run_name, time (n,) s, {column: values (n,) SI})`, overlaid in the given order.
    columns: patterns of the columns to plot (see `select_columns`; None: all).
    x: `time` or a column present in the runs (e.g. `crank_angle.value`), excluded from
    the plotted columns. units: `{column: unit}` for labels (else guessed from names).
    Files: `REQUEST.png` vs time, `REQUEST-vs-XCOLUMN.png` otherwise.
    Raises ValueError for no runs, a missing x column, or patterns that match nothing.
    """
    if not runs:
        raise ValueError("no runs to plot")
    available = list(dict.fromkeys(c for _, _, ch in runs for c in ch))
    if x != TIME_COLUMN and not any(x in ch for _, _, ch in runs):
        raise ValueError(f"x column '{x}' is in none of the runs (columns: {', '.join(available)})")
    chosen = [c for c in select_columns(available, columns) if c != x]
    by_request: dict[str, list[str]] = {}
    for column in chosen:
        by_request.setdefault(request_of(column), []).append(column)
    units = dict(units or {})
    xlabel = _label(x, column_unit(x, units))
    names = [name for name, _, _ in runs]
    subtitle = names[0] if len(runs) == 1 else f"{len(runs)} runs"
    written = []
    for request, columns_of in by_request.items():
        panels = _request_panels(request, columns_of, runs, x, units)
        if not panels:
            continue
        stem = request if x == TIME_COLUMN else f"{request}-vs-{x}"
        title = f"{request} vs {x} - {subtitle}"
        written.append(
            _draw(
                panels,
                title=title,
                xlabel=xlabel,
                target=Path(out_dir) / plot_file_name(stem),
                legend_per_panel=len(runs) == 1,
            )
        )
    return written


def _field(curve: Any, name: str, default: Any = None) -> Any:
    if isinstance(curve, Mapping):
        return curve.get(name, default)
    return getattr(curve, name, default)


@plain_text_plots()  # `$` in a name is a dollar sign
def write_envelope_plots(curves: Iterable[Any], out_dir: Path) -> list[Path]:
    """Write one PNG per envelope curve into `out_dir`; return the paths written.

    Each curve is a mapping or an object with `column` (str), `abscissa_name` (str),
    `x` (m,) abscissa values, `upper` and `lower` (m,) envelope values (SI, NaN = gap),
    `family` (str) and `unit` (str, unit of the column); optional `abscissa_unit`
    (else guessed from `abscissa_name`, e.g. `angle(hinge)` -> rad).
    File: `envelope-FAMILY-COLUMN.png` (unsafe characters replaced by `_`).
    """
    figure = _EnvelopeFigure()
    written = []
    for curve in curves:
        column, family = str(_field(curve, "column")), str(_field(curve, "family", ""))
        abscissa = str(_field(curve, "abscissa_name", "x"))
        x_unit = _field(curve, "abscissa_unit")
        if x_unit is None:
            x_unit = column_unit(abscissa.replace("(", "_").replace(")", ""))
        unit = _field(curve, "unit") or column_unit(column)
        target = Path(out_dir) / plot_file_name(f"envelope-{family}-{column}")
        x, upper, lower = (_field(curve, k) for k in ("x", "upper", "lower"))
        if not np.isfinite(np.asarray(upper, float)).any():
            figure = _EnvelopeFigure()  # nothing to scale to: the limits of a new figure
        figure.set_labels(
            title=f"envelope of {column} vs {abscissa} - family {family}",
            xlabel=_label(abscissa, x_unit),
            ylabel=_label(column, unit),
        )
        written.append(figure.save(x, upper, lower, target))
    return written


class _EnvelopeFigure:
    """One figure drawn again for each envelope curve: its axes, grids, ticks and legend
    are built once (building the ticks was most of a plot's time); per curve only the
    lines, the band, the labels and the limits change. Upper line red, lower blue, the band
    between them grey; one panel, the legend at the right."""

    def __init__(self) -> None:
        self.fig = Figure(figsize=(FIG_WIDTH_IN, figure_height_in(1)), dpi=DPI)
        FigureCanvasAgg(self.fig)
        self.ax = self.fig.subplots()
        self.upper = self.ax.plot([], [], linewidth=1.2, label="upper", color="tab:red")[0]
        self.lower = self.ax.plot([], [], linewidth=1.2, label="lower", color="tab:blue")[0]
        self.grid = _style(self.ax)
        self.fig.subplots_adjust(left=0.1, right=0.84, top=0.88, bottom=0.14)
        self.fig.legend(
            [self.upper, self.lower],
            ["upper", "lower"],
            loc="upper left",
            bbox_to_anchor=(0.855, 0.88),
            fontsize="small",
        )
        self.band: Any = None

    def set_labels(self, *, title: str, xlabel: str, ylabel: str) -> None:
        self.fig.suptitle(title)
        self.ax.set_xlabel(xlabel)
        self.ax.set_ylabel(ylabel)

    def save(self, x: Any, upper: Any, lower: Any, target: Path) -> Path:
        """Draw the curve (x, upper, lower: SI, NaN = gap) and save `target` atomically."""
        xs, hi, lo = (np.asarray(v, dtype=float) for v in (x, upper, lower))
        if self.band is not None:
            self.band.remove()
        self.band = self.ax.fill_between(
            xs, lo, hi, color="0.5", alpha=0.15, linewidth=0, label="envelope"
        )
        self.upper.set_data(xs, hi)
        self.lower.set_data(xs, lo)
        self.ax.set_autoscale_on(True)
        self.ax.relim()
        self.ax.autoscale_view()
        panel = _Panel("", [("upper", xs, hi), ("lower", xs, lo)])
        if _all_below(panel, ZERO_FLOOR):
            self.ax.set_ylim(-1.0, 1.0)
        self.grid.update()
        with atomic_path(target) as tmp:
            self.fig.savefig(tmp, format="png", dpi=DPI, pil_kwargs=PNG_OPTIONS)
        return target
