"""Polar plots and wear maps of clearance joints as PNG (seed 004 figures 5.4, 5.5, 5.11).

For a `polar` request (loadcases.report.wear_map), `write_polar_plots` draws two files per
group of runs (one run, or every run of a sweep overlaid, one colour per run):
- `REQ-polar.png`: three polar panels over the polar angle of the eccentricity (where the
  ball presses on the socket): the relative position of the centres (radial eccentricity,
  mm) with the clearance circle dashed, the contact force F_N (N) and the wear indicator
  F_N * v_rel (W);
- `REQ-wear-map.png`: the wear work accumulated per 10 deg sector (J) as polar bars (one
  ring of bars per run, side by side in each sector).
Matplotlib's Agg canvas, files written atomically (as loadcases.report.plots).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from loadcases.foundation.atomic import atomic_path
from loadcases.foundation.clip import plain_text_plots
from loadcases.report.plots import plot_file_name
from loadcases.report.wear_map import SECTORS, PolarData, polar_data, polar_requests
from loadcases.results.saved import SavedRun

__all__ = ["polar_file_names", "write_polar_plots", "write_runs_polar_plots"]

_DPI = 100
_MM = 1e3


def polar_file_names(request: str, stem: str = "") -> tuple[str, str]:
    """File names of the polar plot and the wear map of `request` (with a `stem` prefix)."""
    prefix = f"{stem}-" if stem else ""
    return (
        plot_file_name(f"{prefix}{request}-polar"),
        plot_file_name(f"{prefix}{request}-wear-map"),
    )


@plain_text_plots()  # `$` in a name is a dollar sign
def _polar_panels(data: list[PolarData], title: str, target: Path) -> Path:
    fig = Figure(figsize=(15.0, 5.6), dpi=_DPI, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, 3, subplot_kw={"projection": "polar"})
    panels = (
        ("relative position of the centres [mm]", lambda d: d.radial * _MM),
        ("contact force F_N [N]", lambda d: d.normal),
        ("wear indicator F_N v_rel [W]", lambda d: d.wear),
    )
    circle = np.linspace(0.0, 2.0 * math.pi, 361)
    for ax, (label, values) in zip(axes, panels):
        for d in data:
            ax.plot(d.angle, values(d), ".", markersize=1.5, label=d.run)
        ax.set_title(label, fontsize="medium", pad=22)
    for d in {d.clearance: d for d in data}.values():
        axes[0].plot(
            circle,
            np.full_like(circle, d.clearance * _MM),
            "--",
            color="0.3",
            linewidth=0.8,
            label=f"clearance {d.clearance * _MM:g} mm",
        )
    fig.legend(
        *axes[0].get_legend_handles_labels(),
        loc="outside lower center",
        fontsize="small",
        ncols=min(4, len(data) + 1),
        markerscale=6,
    )
    fig.suptitle(title)
    with atomic_path(target) as tmp:
        fig.savefig(tmp, format="png", dpi=_DPI)
    return target


@plain_text_plots()  # `$` in a name is a dollar sign
def _wear_map(data: list[PolarData], title: str, target: Path) -> Path:
    fig = Figure(figsize=(8.5, 8.5), dpi=_DPI, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="polar")
    width = 2.0 * math.pi / SECTORS
    bar = width / max(len(data), 1)
    centres = np.arange(SECTORS) * width
    for k, d in enumerate(data):
        offset = (k - 0.5 * (len(data) - 1)) * bar
        ax.bar(centres + offset, d.sectors(), width=bar, label=d.run, alpha=0.8)
    ax.set_title("wear work per 10 deg sector [J]", fontsize="medium")
    fig.legend(loc="outside lower center", fontsize="small", ncols=min(2, len(data)))
    fig.suptitle(title)
    with atomic_path(target) as tmp:
        fig.savefig(tmp, format="png", dpi=_DPI)
    return target


def write_polar_plots(data: list[PolarData], out_dir: Path, *, stem: str = "") -> list[Path]:
    """The polar plot and the wear map of `data` (runs of one polar request, overlaid)
    in `out_dir`; returns the two paths."""
    if not data:
        return []
    out_dir.mkdir(parents=True, exist_ok=True)
    request = data[0].request
    names = polar_file_names(request, stem)
    runs = data[0].run if len(data) == 1 else f"{len(data)} runs"
    return [
        _polar_panels(data, f"{request}: polar plots ({runs})", out_dir / names[0]),
        _wear_map(data, f"{request}: wear map ({runs})", out_dir / names[1]),
    ]


def write_runs_polar_plots(
    runs: list[SavedRun], out_dir: Path, requests: list[str] | None = None
) -> list[Path]:
    """Polar plots and wear maps of saved runs: for each polar request (default: every one
    found), one pair per run (`RUN-REQ-polar.png`, `RUN-REQ-wear-map.png`) and, for several
    runs of one family (a sweep), one pair with them overlaid (`FAMILY-REQ-...`).
    ValueError when a requested polar request is missing from a run."""
    written: list[Path] = []
    families: dict[str, list[SavedRun]] = {}
    for run in runs:
        families.setdefault(run.family, []).append(run)
    for family, members in families.items():
        names = requests or sorted({r for run in members for r in polar_requests(run)})
        for request in names:
            data = [polar_data(run, request) for run in members]
            for d in data:
                written += write_polar_plots([d], out_dir, stem=d.run)
            if len(data) > 1:
                written += write_polar_plots(data, out_dir, stem=family)
    return written
