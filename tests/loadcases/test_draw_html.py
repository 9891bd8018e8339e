"""`loads draw --html`: the page's figure read back from the HTML file (frames, slider,
labels), force arrows against the closed-form reactions of the four-bar, escaping of case
text, and the run of a set."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from loadcases.draw.page import MAX_FRAMES, write_html
from loadcases.draw.scene import ARROW_SHARE
from loadcases.draw.shapes import frame_indices
from loadcases.draw.trajectory import solve_trajectory
from loadcases.inputs.loader import load_case
from loadcases.sets.specs import case_of_run
from tests.verification.references import FourBar, fourbar_static_loads

pytest.importorskip("plotly", reason="the HTML page needs the optional extra loads[html]")

LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library"
FOURBAR = LIBRARY / "verification" / "fourbar_quasistatic.case.yaml"
PRESS_SET = LIBRARY / "examples" / "press_sizing.set.yaml"
CRANK_SPEED = 2 * np.pi  # rad/s, `crank_speed: 360 deg/s` of the four-bar case
FORCES = ("crank_pivot", "pin_c")


def read_figure(page: str) -> dict:
    """data, layout and frames of the plotly figure embedded in a page."""
    decoder = json.JSONDecoder()
    start = page.index("Plotly.newPlot(")
    start = page.index("[", start)
    data, end = decoder.raw_decode(page, start)
    layout, _ = decoder.raw_decode(page, page.index("{", end))
    frames, _ = decoder.raw_decode(page, page.index("[", page.index("Plotly.addFrames(")))
    return {"data": data, "layout": layout, "frames": frames}


def trace(traces: list[dict], name: str) -> dict:
    return next(t for t in traces if t.get("name") == name)


def xyz(t: dict) -> np.ndarray:
    return np.array([[np.nan if v is None else v for v in t[c]] for c in "xyz"]).T


@pytest.fixture(scope="module")
def fourbar():
    return solve_trajectory(load_case(FOURBAR), forces=FORCES)


@pytest.fixture(scope="module")
def page(fourbar, tmp_path_factory) -> tuple[Path, dict]:
    folder = tmp_path_factory.mktemp("html")
    path = write_html(fourbar, folder)
    return path, read_figure(path.read_text(encoding="utf-8"))


def test_page_is_whole_self_contained_and_named_after_the_run(page) -> None:
    """One file `CASE.html` (no temporary file left), plotly.js inside it and no script or
    stylesheet fetched from elsewhere."""
    path, _ = page
    assert path.name == "fourbar-quasistatic.html"
    assert [p.name for p in path.parent.iterdir()] == [path.name]
    text = path.read_text(encoding="utf-8")
    assert len(text) > 3_000_000  # plotly.js (about 4.8 MB) is embedded
    assert not re.search(r"<script[^>]+src=|<link[^>]+href=", text)
    assert "<title>fourbar-quasistatic</title>" in text


def test_one_frame_and_one_slider_step_per_drawn_time(page, fourbar) -> None:
    _, fig = page
    count = min(len(fourbar.time), MAX_FRAMES)
    assert len(fourbar.time) == 201 and len(fig["frames"]) == count == 100
    steps = fig["layout"]["sliders"][0]["steps"]
    assert len(steps) == count
    assert [s["args"][0] for s in steps] == [[f["name"]] for f in fig["frames"]]
    times = fourbar.time[frame_indices(len(fourbar.time), MAX_FRAMES)]
    labels = [s["label"] for s in steps]
    assert [label.split("   ")[0] for label in labels] == [f"{t:.4g} s" for t in times]
    # the forces' magnitudes follow the time: "0.005 s   crank_pivot 46.5 N, pin_c 15.4 N"
    assert all(re.fullmatch(r"\S+ s   crank_pivot \S+ N, pin_c \S+ N", s) for s in labels)
    sizes = {len(f["data"]) for f in fig["frames"]}
    assert sizes == {len(fig["data"])}  # every frame updates the same traces


def test_labels_name_every_body_joint_and_force(page) -> None:
    _, fig = page
    data = fig["data"]
    bodies = {t["name"] for t in data if t["type"] == "scatter3d" and t["mode"] == "lines"}
    assert {"crank", "coupler", "rocker"} <= bodies
    joints = ", ".join(trace(data, "joints")["text"])
    assert all(j in joints for j in ("crank_pivot", "pin_b", "pin_c", "rocker_pivot"))
    assert trace(data, "body names")["text"] == ["<i>crank</i>", "<i>coupler</i>", "<i>rocker</i>"]
    forces = trace(data, "reaction force names")
    assert forces["text"] == list(FORCES)
    assert [t.split(":")[0] for t in forces["hovertext"]] == list(FORCES)
    for frame in fig["frames"]:  # 3-D labels keep their text (plotly shrinks changed ones)
        for t in frame["data"]:
            if "text" in t:
                assert t["text"] == trace(data, t["name"])["text"], t["name"]


def test_arrow_lengths_follow_the_closed_form_reactions(page, fourbar) -> None:
    """At every frame, each arrow (joint point to tip) is `scale * |F|` with |F| the in-plane
    reaction of planar statics (tests/verification/references.fourbar_static_loads) and
    the scale the page states (4 digits), within 1e-5 m of the 0.165 m longest arrow
    (measured 3.8e-6 m: the scale's 4 digits and positions rounded to 1 µm in the page).
    The longest arrow over the run is ARROW_SHARE of the mechanism's size (1e-6 m)."""
    _, fig = page
    scale = float(re.search(r"arrows of ([0-9.e+-]+) m per kN", fig["layout"]["title"]["text"])[1])
    scale /= 1000.0  # m per N
    indices = frame_indices(len(fourbar.time), MAX_FRAMES)
    theta = CRANK_SPEED * fourbar.time[indices]
    ref = fourbar_static_loads(theta, FourBar())
    longest = 0.0
    for frame, row in zip(fig["frames"], range(len(indices))):
        shafts = xyz(trace(frame["data"], "reaction forces")).reshape(-1, 3, 3)
        lengths = np.linalg.norm(shafts[:, 1] - shafts[:, 0], axis=1)
        expected = [scale * np.hypot(ref[f"{j}_fx"][row], ref[f"{j}_fy"][row]) for j in FORCES]
        assert lengths == pytest.approx(expected, abs=1e-5)
        longest = max(longest, *lengths)
    cloud = np.concatenate(list(fourbar.positions.values()))
    size = float(np.max(np.ptp(cloud, axis=0)))
    assert longest == pytest.approx(ARROW_SHARE * size, abs=1e-6)


def test_text_of_the_case_is_escaped(tmp_path: Path) -> None:
    """A case name with markup is shown as text: no tag of it reaches the page."""
    evil = '<img src=x onerror="alert(1)">'
    source = FOURBAR.read_text(encoding="utf-8").replace(
        "case: fourbar-quasistatic", f"case: '{evil}'"
    )
    source = source.replace("end: 1.0", "end: 0.01")
    case = tmp_path / "evil.case.yaml"
    case.write_text(source, encoding="utf-8")
    path = write_html(solve_trajectory(load_case(case)), tmp_path / "out")
    text = path.read_text(encoding="utf-8")
    assert "<img" not in text and 'onerror="alert' not in text
    assert "<title>&lt;img src=x onerror=&quot;alert(1)&quot;&gt;</title>" in text


def test_run_of_a_set_is_loaded_with_its_values() -> None:
    """`case_of_run` loads the run's case with the run's swept values; a wrong name gives
    the names of the set's runs."""
    run = "press-stroke[crank_speed=360deg_per_s,press_force=1500N]"
    cf = case_of_run(PRESS_SET, run)
    assert not isinstance(cf, list)
    assert cf.parameters["press_force"] == 1500.0
    assert cf.parameters["crank_speed"] == pytest.approx(2 * np.pi)
    names = case_of_run(PRESS_SET, "press-stroke")
    assert isinstance(names, list) and run in names and len(names) == 8
