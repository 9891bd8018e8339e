"""Pictures of a mechanism trajectory (`loads draw`): PNG at chosen times, GIF animation.

Projection onto a plane: `xy`, `yz`, `xz` (global axes) or `auto`: the plane of the two
largest principal spreads of all marker positions over the run (snapped to the nearest
global plane when its normal is within 15 degrees of a global axis, so that CAD-aligned
mechanisms keep their axes). Bodies are outlines through their joint and point markers,
joints are circles with their names, points small dots, springs zigzags, wires dashed,
seals thick translucent lines, contacts a circle (roller, sphere) with the plane or profile
it runs on; a contact's name is printed next to its roller. Where the run starts away from
the drawn geometry (initial values, motions, another assembly branch), the drawing is shown
under it as a ghost: grey dashed outlines, its joints as crosses.
"""

from __future__ import annotations

import io
import re
import tempfile
from pathlib import Path

import numpy as np

from loadcases.draw.shapes import frame_indices, outline_order, zigzag
from loadcases.draw.trajectory import Trajectory
from loadcases.foundation.atomic import atomic_path, atomic_write_bytes
from loadcases.foundation.clip import plain_text_plots

__all__ = ["DPI", "FIGURE_SIZE", "VIEWS", "projection", "slug", "write_animation", "write_pngs"]

FIGURE_SIZE = (8.0, 6.0)
"""inch: figure size; with DPI the PNG is 800 x 600 pixels."""
DPI = 100
VIEWS = ("auto", "xy", "yz", "xz")
_AXES = {"xy": (0, 1), "yz": (1, 2), "xz": (0, 2)}
_SNAP_COS = np.cos(np.radians(15.0))
_MAX_FRAMES = 60
_GIF_FPS = 12
_GRID = 1e-9  # m: axis limits and label anchors are drawn on this grid
_LABEL_ITERATIONS = 200  # adjustText passes per picture (a count, not a time: reproducible)
_COLOURS = (
    "tab:blue",
    "tab:orange",
    "tab:green",
    "tab:red",
    "tab:purple",
    "tab:brown",
    "tab:pink",
    "tab:olive",
    "tab:cyan",
)


def projection(traj: Trajectory, view: str) -> tuple[np.ndarray, tuple[str, str]]:
    """(2 x 3 matrix projecting global positions onto the picture, axis labels)."""
    if view in _AXES:
        i, j = _AXES[view]
        basis = np.eye(3)[[i, j]]
        return basis, (f"{'xyz'[i]} [m]", f"{'xyz'[j]} [m]")
    if view != "auto":
        raise ValueError(f"unknown view '{view}': use one of {', '.join(VIEWS)}")
    cloud = np.concatenate([p for p in traj.positions.values() if len(p)] or [np.zeros((1, 3))])
    _, _, vt = np.linalg.svd(cloud - cloud.mean(axis=0), full_matrices=False)
    normal = vt[-1] if vt.shape[0] == 3 else np.array([0.0, 0.0, 1.0])
    axis = int(np.argmax(np.abs(normal)))
    if abs(normal[axis]) >= _SNAP_COS:
        return projection(traj, {2: "xy", 0: "yz", 1: "xz"}[axis])
    return vt[:2], ("u [m] (principal)", "v [m] (principal)")


def _draw_frame(ax, traj: Trajectory, k: int, basis: np.ndarray) -> list:
    """Draw the mechanism at output index k on the axes; returns the name labels."""
    from matplotlib.patches import Circle

    sk = traj.skeleton
    texts = []
    at = {m: basis @ traj.positions[m][k] for m in sk.markers}
    for n, (body, markers) in enumerate(sk.bodies.items()):
        if body == "ground":
            continue
        pts = np.array([at[m] for m in markers])
        ring = pts[outline_order(pts)]
        colour = _COLOURS[n % len(_COLOURS)]
        ax.plot(ring[:, 0], ring[:, 1], "-", color=colour, lw=2.0, alpha=0.85)
        ax.fill(ring[:, 0], ring[:, 1], color=colour, alpha=0.08)
        c = np.array([at[m] for m in markers]).mean(axis=0)
        texts.append(ax.text(*c, body, fontsize=7, color=colour, ha="center", style="italic"))
    for name, kind, a, b in sk.links:
        pa, pb = at[a], at[b]
        if kind == "spring":
            d = (pb - pa) / max(float(np.hypot(*(pb - pa))), 1e-12)
            z = zigzag(pa, pb, np.array([-d[1], d[0]]))
            ax.plot(z[:, 0], z[:, 1], "-", color="tab:green", lw=1.2)
        elif kind == "wire":
            ax.plot([pa[0], pb[0]], [pa[1], pb[1]], "--", color="black", lw=1.2)
        else:
            ax.plot([pa[0], pb[0]], [pa[1], pb[1]], "-", color="dimgray", lw=5, alpha=0.35)
        texts.append(ax.text(*((pa + pb) / 2), name, fontsize=7, color="darkgreen"))
    for name, kind, markers, radius in sk.contacts:
        pts = np.array([at[m] for m in markers])
        if kind == "circle":
            ax.add_patch(Circle(pts[0], radius, fill=False, color="crimson", lw=1.2))
            texts.append(ax.text(*pts[0], name, fontsize=7, color="crimson"))
        else:
            closed = np.vstack([pts, pts[:1]]) if kind == "plane" else pts
            ax.plot(closed[:, 0], closed[:, 1], "-", color="crimson", lw=1.5)
    for marker in sk.points.values():
        ax.plot(*at[marker], ".", color="gray", ms=4)
    labels: dict[tuple[float, float], list[str]] = {}  # coincident joints share one label
    for name, marker in sk.joints.items():
        ax.plot(*at[marker], "o", mfc="white", mec="black", ms=6)
        labels.setdefault(tuple(np.round(at[marker], 4)), []).append(name)
    for place, names in labels.items():
        texts.append(ax.text(*place, ", ".join(names), fontsize=8))
    return texts


def _draw_ghost(ax, traj: Trajectory, basis: np.ndarray) -> list:
    """The drawn (design) geometry in grey dashes under the run: body outlines and joints
    as crosses; returns the lines drawn (none where the run starts at the drawing)."""
    if not traj.assembled_off_drawing():
        return []
    sk, lines = traj.skeleton, []
    at = {m: basis @ traj.drawn(m) for m in sk.markers}
    for body, markers in sk.bodies.items():
        if body == "ground":
            continue
        pts = np.array([at[m] for m in markers])
        ring = pts[outline_order(pts)]
        lines += ax.plot(ring[:, 0], ring[:, 1], "--", color="gray", lw=1.0, alpha=0.6)
    for marker in sk.joints.values():
        lines += ax.plot(*at[marker], "x", color="gray", ms=5, alpha=0.8)
    return lines


def _spread_labels(ax, texts: list, offsets: dict[str, np.ndarray] | None = None) -> None:
    """Move the name labels apart so that none hides another (adjustText), each joined to
    its anchor by a thin line when moved. With `offsets` (label -> data offset from its
    anchor): labels already spread on an earlier frame keep their offset (an animation's
    labels travel with their anchors instead of jumping), new ones are spread and added."""
    from adjustText import adjust_text

    for t in texts:  # adjustText amplifies round-off into another picture: anchors on a grid
        t.set_position(_on_grid(np.array(t.get_position(), float)))
    anchors = {id(t): np.array(t.get_position(), float) for t in texts}
    fresh = [t for t in texts if offsets is None or t.get_text() not in offsets]
    known = offsets if offsets is not None else {}
    for t in texts:
        if t not in fresh:
            moved = anchors[id(t)] + known[t.get_text()]
            t.set_position(moved)
            if np.any(known[t.get_text()]):
                ax.plot(*np.column_stack([anchors[id(t)], moved]), "-", color="gray", lw=0.4)
    placed = [t for t in texts if t not in fresh]
    if len(fresh) > 1 or (fresh and placed):
        adjust_text(
            fresh,
            ax=ax,
            iter_lim=_LABEL_ITERATIONS,
            ensure_inside_axes=True,
            prevent_crossings=False,
            objects=placed or None,
            arrowprops={"arrowstyle": "-", "color": "gray", "lw": 0.4},
        )
    if offsets is not None:
        offsets.update(
            {t.get_text(): np.array(t.get_position(), float) - anchors[id(t)] for t in fresh}
        )


def _limits(traj: Trajectory, basis: np.ndarray) -> tuple[tuple[float, float], tuple[float, float]]:
    """Axis limits holding every marker over the whole run, with a margin, widened to the
    shape of the picture (room for the labels of a slender mechanism)."""
    cloud = np.concatenate([p @ basis.T for p in traj.positions.values() if len(p)])
    low, high = cloud.min(axis=0), cloud.max(axis=0)
    pad = 0.08 * max(float(np.max(high - low)), 1e-3)
    low, high = low - pad, high + pad
    span, centre = high - low, (low + high) / 2
    shape = FIGURE_SIZE[0] / FIGURE_SIZE[1]  # width / height of the picture
    span = np.maximum(span, [span[1] * shape, span[0] / shape])
    return (
        (float(_on_grid(centre[0] - span[0] / 2)), float(_on_grid(centre[0] + span[0] / 2))),
        (float(_on_grid(centre[1] - span[1] / 2)), float(_on_grid(centre[1] + span[1] / 2))),
    )


def _on_grid(values):
    """Values (m) rounded to _GRID: a picture the same whatever the solver's round-off."""
    return np.round(np.asarray(values, float) / _GRID) * _GRID


def _figure(traj: Trajectory, view: str, *, steady_labels: bool = False):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    basis, labels = projection(traj, view)
    fig, ax = plt.subplots(figsize=FIGURE_SIZE, dpi=DPI)
    xlim, ylim = _limits(traj, basis)
    offsets: dict[str, np.ndarray] | None = {} if steady_labels else None

    def render(k: int) -> None:
        ax.clear()
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ax.set_aspect("equal", adjustable="box")
        ghost = _draw_ghost(ax, traj, basis)
        texts = _draw_frame(ax, traj, k, basis)
        ax.set_xlabel(labels[0])
        ax.set_ylabel(labels[1])
        ax.grid(True, lw=0.3, alpha=0.5)
        drawn = "   (grey dashes: as drawn)" if ghost else ""
        ax.set_title(f"{traj.case}   t = {traj.time[k]:.4g} s{drawn}", fontsize=10)
        _spread_labels(ax, texts, offsets)

    return fig, render


def slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.=\-]+", "_", text)


@plain_text_plots()  # `$` in a name is a dollar sign
def write_pngs(
    traj: Trajectory, times: list[float], out_dir: Path, *, view: str = "auto"
) -> list[Path]:
    """One PNG (800 x 600 px) per requested time (s; nearest output time), written
    atomically as `CASE-t<time>.png` in `out_dir`; returns the files."""
    import matplotlib.pyplot as plt

    if len(traj.time) == 0:
        raise ValueError(f"{traj.case}: the run produced no output time ({traj.message})")
    fig, render = _figure(traj, view)
    written = []
    try:
        for t in times:
            k = traj.index_at(t)
            render(k)
            target = Path(out_dir) / f"{slug(traj.case)}-t{traj.time[k]:.4f}.png"
            with atomic_path(target) as tmp:
                fig.savefig(tmp, format="png", dpi=DPI)
            written.append(target)
    finally:
        plt.close(fig)
    return written


@plain_text_plots()  # `$` in a name is a dollar sign
def write_animation(
    traj: Trajectory, out_dir: Path, *, view: str = "auto"
) -> tuple[list[Path], str]:
    """Animate the run (at most 60 frames) as `CASE.gif` (Pillow), or, without Pillow,
    as numbered PNG frames `CASE-frame-NNN.png`; returns (files, what was written)."""
    import matplotlib.pyplot as plt
    from matplotlib import animation

    if len(traj.time) == 0:
        raise ValueError(f"{traj.case}: the run produced no output time ({traj.message})")
    fig, render = _figure(traj, view, steady_labels=True)
    frames = frame_indices(len(traj.time), _MAX_FRAMES)
    try:
        if animation.PillowWriter.isAvailable():
            anim = animation.FuncAnimation(fig, render, frames=frames, blit=False)
            with tempfile.TemporaryDirectory() as tmp:
                gif = Path(tmp) / "animation.gif"
                anim.save(gif, writer=animation.PillowWriter(fps=_GIF_FPS), dpi=DPI)
                target = Path(out_dir) / f"{slug(traj.case)}.gif"
                atomic_write_bytes(target, gif.read_bytes())
            return [target], f"GIF of {len(frames)} frames"
        written = []
        for i, k in enumerate(frames):
            render(k)
            target = Path(out_dir) / f"{slug(traj.case)}-frame-{i:03d}.png"
            buffer = io.BytesIO()
            fig.savefig(buffer, format="png", dpi=DPI)
            atomic_write_bytes(target, buffer.getvalue())
            written.append(target)
        return written, f"{len(frames)} numbered PNG frames (Pillow is not installed: no GIF)"
    finally:
        plt.close(fig)
