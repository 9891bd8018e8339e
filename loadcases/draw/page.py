"""An interactive 3-D view of a run as one self-contained HTML page (`loads draw --html`).

plotly draws the scene (`loadcases.draw.scene`) in WebGL; the page embeds plotly.js, so it
opens without a network. Drag to orbit, scroll to zoom; the slider picks the output time
and Play runs the motion (at most `MAX_FRAMES` evenly spread output times). plotly is the
optional extra `loads[html]`: `plotly_missing()` says how to install it.
"""

from __future__ import annotations

import html
import importlib.util
from pathlib import Path

import numpy as np

from loadcases.draw.render import projection
from loadcases.draw.scene import Scene, force_summary, frame_traces, scene_of
from loadcases.draw.shapes import frame_indices
from loadcases.draw.trajectory import Trajectory
from loadcases.foundation.atomic import atomic_write_text
from loadcases.foundation.clip import visible

__all__ = ["MAX_FRAMES", "figure_of", "html_page", "plotly_missing", "write_html"]

MAX_FRAMES = 100
_FRAME_MS = 80  # ms per frame when playing: 100 frames in 8 s
_PAD = 0.08  # share of the mechanism's size added round the scene
_EYE = 1.7  # camera distance, in plotly's scene units
_DIV_ID = "loads-draw"
# Pausing (or moving the slider) while playing makes plotly.js reject the promise of the
# interrupted animation with no reason, which browsers report as an uncaught error; only
# that rejection is marked handled, any other still reaches the console.
_QUIET_INTERRUPTED_ANIMATION = (
    "<script>window.addEventListener('unhandledrejection', function (event) {\n"
    "  if (event.reason === undefined) { event.preventDefault(); }\n"
    "});</script>\n"
)
INSTALL_HINT = "pip install 'loads[html]'"


def plotly_missing() -> str | None:
    """None when plotly is installed, else what to do (the HTML page needs it)."""
    if importlib.util.find_spec("plotly") is not None:
        return None
    return f"the 3-D page needs plotly, an optional extra of loads: {INSTALL_HINT}"


def _ranges(traj: Trajectory, scene: Scene) -> np.ndarray:
    """(3, 2) axis ranges (m) holding every marker and force arrow over the run."""
    clouds = [p for p in traj.positions.values() if len(p)]
    for joint, force in traj.reactions.items():
        clouds.append(traj.positions[traj.skeleton.joints[joint]] + scene.metres_per_newton * force)
    cloud = np.concatenate(clouds)
    low, high = cloud.min(axis=0), cloud.max(axis=0)
    centre, half = (low + high) / 2, np.maximum(high - low, scene.size * 0.2) / 2
    half += _PAD * scene.size
    return np.column_stack([centre - half, centre + half])


def _camera(traj: Trajectory, view: str) -> dict:
    """Look along the normal of the view's plane (`auto`: the mechanism's main plane), a
    little from the side so that depth shows."""
    plane, _ = projection(traj, view)
    normal = np.cross(plane[0], plane[1])
    eye = _EYE * (0.85 * normal + 0.3 * plane[0] + 0.3 * plane[1])
    return {
        "eye": dict(zip("xyz", eye.round(4).tolist())),
        "up": dict(zip("xyz", plane[1].round(4).tolist())),
    }


def _scene_layout(traj: Trajectory, scene: Scene, view: str) -> dict:
    ranges = _ranges(traj, scene)
    spans = ranges[:, 1] - ranges[:, 0]
    axes = {
        f"{c}axis": {"title": {"text": f"{c} [m]"}, "range": ranges[i].round(6).tolist()}
        for i, c in enumerate("xyz")
    }
    return axes | {
        "aspectmode": "manual",
        "aspectratio": dict(zip("xyz", (spans / spans.max()).round(4).tolist())),
        "camera": _camera(traj, view),
        "uirevision": "keep",
    }


def _controls(labels: list[str]) -> dict:
    """The time slider (one step per frame, its label shown as the current value) and the
    Play / Pause buttons."""
    still = {"mode": "immediate", "frame": {"duration": 0, "redraw": True}, "transition": {}}
    steps = [
        {"method": "animate", "label": label, "args": [[str(i)], still]}
        for i, label in enumerate(labels)
    ]
    play = {"frame": {"duration": _FRAME_MS, "redraw": True}, "fromcurrent": True}
    buttons = [
        {"label": "Play", "method": "animate", "args": [None, play]},
        {"label": "Pause", "method": "animate", "args": [[None], still]},
    ]
    return {
        "sliders": [
            {
                "active": 0,
                "steps": steps,
                "currentvalue": {"prefix": "t = ", "font": {"color": "black"}},
                "font": {"color": "rgba(0, 0, 0, 0)"},  # a label per step would overlap
                "pad": {"t": 30},
            }
        ],
        "updatemenus": [
            {"type": "buttons", "buttons": buttons, "direction": "left", "x": 0, "y": 0}
        ],
    }


def _html(text: str) -> str:
    """`text` for the page: markup escaped, hidden characters written as escapes."""
    return html.escape(visible(text))


def _title(traj: Trajectory, scene: Scene) -> str:
    title = _html(traj.case)
    if traj.reactions:
        title += (
            f"<br><sub>reaction forces on each joint's first body: arrows of "
            f"{scene.metres_per_newton * 1000:.4g} m per kN</sub>"
            if scene.metres_per_newton > 0
            else "<br><sub>reaction forces: zero throughout</sub>"
        )
    if traj.status != "ok":
        title += f"<br><sub>the run failed: {_html(traj.message)}</sub>"
    return title


def _step_label(traj: Trajectory, k: int) -> str:
    """`0.12 s` and, with force arrows, `   pivot 52.02 N, hinge 21.45 N`."""
    label = f"{float(traj.time[k]):.4g} s"
    return f"{label}   {force_summary(traj, k)}" if traj.reactions else label


def figure_of(traj: Trajectory, *, view: str = "auto") -> dict:
    """The plotly figure (a dict: data, layout, frames) of a trajectory with output times."""
    scene = scene_of(traj)
    indices = frame_indices(len(traj.time), MAX_FRAMES)
    frames = [{"name": str(i), "data": frame_traces(traj, scene, k)} for i, k in enumerate(indices)]
    layout = {
        "title": {"text": _title(traj, scene)},
        "scene": _scene_layout(traj, scene, view),
        "margin": {"l": 0, "r": 0, "t": 70, "b": 0},
    } | _controls([_step_label(traj, k) for k in indices])
    return {"data": frames[0]["data"], "layout": layout, "frames": frames}


def html_page(traj: Trajectory, *, view: str = "auto") -> str:
    """The whole page: plotly.js embedded, the figure, not playing until asked."""
    import plotly.io as pio

    figure = figure_of(traj, view=view)
    figure["layout"]["template"] = pio.templates["plotly_white"].to_plotly_json()
    body = pio.to_html(
        figure,
        include_plotlyjs=True,
        full_html=False,
        auto_play=False,
        div_id=_DIV_ID,
        default_height="100vh",
        validate=False,
    )
    return (
        '<!DOCTYPE html>\n<html>\n<head>\n<meta charset="utf-8">\n'
        f"<title>{_html(traj.case)}</title>\n"
        "<style>html, body { margin: 0; height: 100%; }</style>\n"
        f"{_QUIET_INTERRUPTED_ANIMATION}"
        f"</head>\n<body>\n{body}\n</body>\n</html>\n"
    )


def write_html(traj: Trajectory, out_dir: Path, *, view: str = "auto") -> Path:
    """Write the page as `RUN.html` in `out_dir`, whole or not at all; returns the file."""
    from loadcases.draw.render import slug

    if len(traj.time) == 0:
        raise ValueError(f"{traj.case}: the run produced no output time ({traj.message})")
    return atomic_write_text(Path(out_dir) / f"{slug(traj.case)}.html", html_page(traj, view=view))
