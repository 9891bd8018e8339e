"""The files of a convergence study (`loads converge`): the table (CSV) and the diagram
(PNG) of every quantity against the parameter, each written whole or not at all.

`NAME.convergence.csv`: one row per quantity; columns `quantity`, `unit` (SI), one column
per value of the parameter (`PARAMETER=TEXT [unit]`, the unit of the row), then
`converged_at [PARAMETER]` (empty: not converged), `change_at_first [%]` (the first value's
relative difference from the last) and `note` (`round-off`, `not converged`); after them the
rows `cost.steps [-]` and `cost.cpu_seconds [s]` of each run.

`NAME.convergence.png`: each quantity's relative difference from its value at the last
parameter value (%, linear within the tolerance band, logarithmic beyond) against the
parameter, the tolerance band shaded; round-off quantities
left out. Lines are labelled for the quantities that leave the band (at most `_LABELLED`).
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

from loadcases.foundation.atomic import atomic_path, atomic_write_text
from loadcases.foundation.clip import plain_text_plots
from loadcases.studies.convergence import Convergence, Quantity

__all__ = ["convergence_csv_text", "write_convergence_files"]

_LABELLED = 12  # legend entries at most: the quantities that move most
_DPI = 100


def _number(value: float) -> str:
    return "" if not math.isfinite(value) else repr(float(value))


def _note(q: Quantity) -> str:
    if q.noise:
        return "round-off"
    return "" if q.converged_at is not None else "not converged"


def convergence_csv_text(study: Convergence) -> str:
    """The table as CSV text (values SI, 17 significant digits as the results files)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    p = study.parameter
    writer.writerow(
        ["quantity", "unit"]
        + [f"{p}={t} [unit]" for t in study.texts]
        + [f"converged_at [{p}]", "change_at_first [%]", "note"]
    )
    for q in study.quantities:
        at = "" if q.converged_at is None else study.texts[q.converged_at]
        writer.writerow(
            [q.name, q.unit]
            + [_number(v) for v in q.values]
            + [at, _number(100.0 * q.change(0)), _note(q)]
        )
    writer.writerow(["cost.steps", "-"] + [str(r.steps) for r in study.runs] + ["", "", ""])
    writer.writerow(
        ["cost.cpu_seconds", "s"]
        + [_number(r.cpu_seconds) for r in study.runs]
        + ["", "", "" if not study.failed else "failed: " + ", ".join(r.text for r in study.failed)]
    )
    return out.getvalue()


def _largest_change(q: Quantity) -> float:
    """The largest relative difference of a quantity from its last value (0 if none)."""
    changes = [abs(q.change(i)) for i in range(len(q.values))]
    return max((c for c in changes if math.isfinite(c)), default=0.0)


@plain_text_plots()
def _write_png(study: Convergence, path: Path) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import FuncFormatter

    shown = [q for q in study.quantities if not q.noise]
    moving = sorted(shown, key=lambda q: -_largest_change(q))
    labelled = {q.name for q in moving[:_LABELLED] if q.converged_at != 0}
    figure = Figure(figsize=(12.0, 6.0), dpi=_DPI)
    figure.subplots_adjust(left=0.08, right=0.72)
    FigureCanvasAgg(figure)
    axes = figure.add_subplot(1, 1, 1)
    band = 100.0 * study.tolerance
    axes.axhspan(-band, band, color="0.9", label=f"tolerance +/-{band:g} %")
    for q in shown:
        changes = [100.0 * q.change(i) for i in range(len(q.values))]
        label = q.name if q.name in labelled else None
        axes.plot(study.values, changes, marker="o", linewidth=1.0, label=label)
    axes.set_xlabel(f"{study.parameter} [SI]")
    axes.set_ylabel("difference from the last value [%] (symmetric log)")
    axes.set_title(
        f"{study.case}: convergence in {study.parameter} "
        f"({len(shown)} quantities, {len(study.unconverged())} not converged)"
    )
    # symmetric log beyond the band: a 1 % band and a 5000 % outlier on one readable axis
    axes.set_yscale("symlog", linthresh=band)
    axes.yaxis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:g}"))  # no math text
    axes.grid(True, linewidth=0.3)
    axes.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
    with atomic_path(path) as tmp:
        figure.savefig(tmp, format="png")


def write_convergence_files(study: Convergence, folder: Path) -> list[Path]:
    """Write `CASE.convergence.csv` and `CASE.convergence.png` into `folder`; their paths."""
    base = Path(folder) / study.case.replace("/", "_")
    table, diagram = Path(f"{base}.convergence.csv"), Path(f"{base}.convergence.png")
    atomic_write_text(table, convergence_csv_text(study))
    _write_png(study, diagram)
    return [table, diagram]
