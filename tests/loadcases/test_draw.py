"""`loads draw`: marker trajectories follow the solved mechanism; one PNG per time, of the
documented size; the GIF (or the frames without Pillow) is written."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from loadcases.draw.render import DPI, FIGURE_SIZE, _figure, projection, write_animation, write_pngs
from loadcases.draw.trajectory import trajectory_of_file

LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library"
FOURBAR = LIBRARY / "verification" / "fourbar_quasistatic.case.yaml"


@pytest.fixture(scope="module")
def fourbar():
    return trajectory_of_file(FOURBAR)


def test_markers_keep_body_distances(fourbar):
    """Two markers of one rigid body keep their design distance at every time (1e-9 m)."""
    sk = fourbar.skeleton
    _body, markers = next((b, m) for b, m in sk.bodies.items() if b != "ground" and len(m) >= 2)
    a, b = fourbar.positions[markers[0]], fourbar.positions[markers[1]]
    design = np.linalg.norm(np.subtract(sk.markers[markers[0]][1], sk.markers[markers[1]][1]))
    assert np.allclose(np.linalg.norm(a - b, axis=1), design, atol=1e-9)
    assert np.ptp(a, axis=0).max() + np.ptp(b, axis=0).max() > 1e-3  # the body does move


def test_pngs_one_per_time_of_documented_size(fourbar, tmp_path):
    times = [0.0, float(fourbar.time[-1])]
    files = write_pngs(fourbar, times, tmp_path, view="xy")
    assert len(files) == 2 and all(f.is_file() for f in files)
    expected = (int(FIGURE_SIZE[0] * DPI), int(FIGURE_SIZE[1] * DPI))
    for f in files:
        with Image.open(f) as image:
            assert image.size == expected


def test_auto_view_of_planar_mechanism_is_its_plane(fourbar):
    _basis, labels = projection(fourbar, "auto")
    assert labels == ("x [m]", "y [m]")


@pytest.mark.slow
def test_animation_written(fourbar, tmp_path):
    files, what = write_animation(fourbar, tmp_path)
    assert files and all(f.is_file() and f.stat().st_size > 0 for f in files)
    assert "GIF" in what or "frames" in what


def _overlapping_labels(fig) -> tuple[int, int]:
    """(pairs of name labels whose boxes overlap, labels) on the picture."""
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for t in fig.axes[0].texts]
    return sum(a.overlaps(b) for a, b in itertools.combinations(boxes, 2)), len(boxes)


def test_labels_of_a_crowded_mechanism_are_spread(monkeypatch):
    """The opened door seen from fwd has 26 name labels within 0.7 m: at their anchors 64
    pairs overlap; spread, at most 2 do (1 measured since the anchors are put on a grid;
    0, 2 or 4 before, with the solver's round-off). The spreading is deterministic."""
    import matplotlib.pyplot as plt

    import loadcases.draw.render as render_module

    door = trajectory_of_file(LIBRARY / "door" / "opened.case.yaml")
    counts = []
    for spread in (False, True, True):
        if not spread:
            monkeypatch.setattr(
                render_module, "_spread_labels", lambda ax, texts, offsets=None: None
            )
        else:
            monkeypatch.undo()
        fig, render = _figure(door, "yz")
        render(0)
        fig.canvas.draw()
        counts.append(_overlapping_labels(fig))
        plt.close(fig)
    (before, n), (after, _), (again, _) = counts
    assert n >= 20 and before >= 30
    assert after <= 2 and again == after


def test_spread_labels_do_not_depend_on_round_off():
    """Anchors moved by about 1e-15 m (the solver's round-off: a change of summation order
    moved the opened door's points by at most 9e-16 m) give the same spread labels, to the
    bit. adjustText amplifies such differences: the door's overlapping label pairs were 0,
    2 or 4 for anchors 1e-15 m apart, so the anchors go on a grid of 1e-9 of the axes
    first."""
    import matplotlib.pyplot as plt

    door = trajectory_of_file(LIBRARY / "door" / "opened.case.yaml")
    exact = {name: np.array(p, float) for name, p in door.positions.items()}
    rng = np.random.default_rng(3)
    placed = []
    for shift in (0.0, 1e-15):
        for name, p in exact.items():
            door.positions[name] = p + shift * rng.standard_normal(p.shape)
        fig, render = _figure(door, "yz")
        render(0)
        placed.append([t.get_position() for t in fig.axes[0].texts])
        plt.close(fig)
    assert len(placed[0]) >= 20 and placed[0] == placed[1]
