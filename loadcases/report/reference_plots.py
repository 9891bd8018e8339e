"""PNG plots of a set's reference curves: per curve and column, the runs' curves (lines)
with the reference's points (markers) over the abscissa, in the report's units, and the
largest difference in the title (`reference-CURVE-COLUMN.png`)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from loadcases.foundation.atomic import atomic_path
from loadcases.foundation.clip import plain_text_plots
from loadcases.report.plots import DPI, FIG_WIDTH_IN, PNG_OPTIONS, plot_file_name
from loadcases.report.reference_curves import Overlay

__all__ = ["write_reference_plots"]


def _label(name: str, unit: str) -> str:
    return f"{name} [{unit}]" if unit else name


def write_reference_plots(overlays: Sequence[Overlay], out_dir: Path) -> list[Path]:
    """One PNG per curve and column (its runs together); the paths written."""
    groups: dict[tuple[str, str], list[Overlay]] = {}
    for overlay in overlays:
        groups.setdefault((overlay.curve, overlay.column), []).append(overlay)
    written = []
    for (curve, column), group in groups.items():
        target = Path(out_dir) / plot_file_name(f"reference-{curve}-{column}")
        written.append(_plot(curve, column, group, target))
    return written


def _plot(curve: str, column: str, group: list[Overlay], target: Path) -> Path:
    with plain_text_plots():
        fig = Figure(figsize=(FIG_WIDTH_IN, 5.0), dpi=DPI)
        FigureCanvasAgg(fig)
        ax = fig.subplots()
        first = group[0]
        for overlay in group:
            ax.plot(np.asarray(overlay.x), np.asarray(overlay.y), linewidth=1.2, label=overlay.run)
        ax.plot(first.ref_x, first.ref_y, "o", markersize=4, color="k", label=first.label)
        worst = max(
            (o.difference for o in group if o.difference.max_difference is not None),
            key=lambda d: abs(d.max_difference or 0.0),
            default=None,
        )
        title = f"{curve}: {column} against {first.label}"
        if worst is not None:
            title += (
                f"\nlargest difference {worst.max_difference:.4g} {first.unit} "
                f"at {worst.at:.4g} {first.abscissa_unit} ({worst.run})"
            )
        fig.suptitle(title, fontsize="medium")
        ax.set_xlabel(_label(first.abscissa, first.abscissa_unit))
        ax.set_ylabel(_label(column, first.unit))
        ax.grid(True, linewidth=0.5, alpha=0.5)
        ax.legend(fontsize="small")
        target.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(target) as tmp:
            fig.savefig(tmp, format="png", dpi=DPI, pil_kwargs=PNG_OPTIONS)
    return target
