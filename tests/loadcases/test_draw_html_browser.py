"""`loads draw --html` opened in a real headless browser (Debian's chromium through
playwright): the page renders its WebGL scene with no error and no network request, the
slider has one step per frame, Play moves it, and the picture is not blank.

Skipped when /usr/bin/chromium or the playwright package is missing, unless
LOADS_REQUIRE_BROWSER=1 (CI sets it): then it fails.
"""

from __future__ import annotations

import importlib.util
import io
import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from loadcases.draw.page import MAX_FRAMES, plotly_missing, write_html
from loadcases.draw.trajectory import solve_trajectory
from loadcases.inputs.loader import load_case

CHROMIUM = Path("/usr/bin/chromium")
CASE = (
    Path(__file__).resolve().parents[2]
    / "loadcases/library/verification/fourbar_quasistatic.case.yaml"
)
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
VIEWPORT = {"width": 1000, "height": 750}
FORCE_RGB = np.array([0xD0, 0x02, 0x1B])  # the arrows' colour (loadcases.draw.scene)


def _missing() -> str | None:
    if not CHROMIUM.is_file():
        return f"{CHROMIUM} is not installed (apt-get install chromium)"
    if importlib.util.find_spec("playwright") is None:
        return "the playwright package is not installed (pip install playwright)"
    return plotly_missing()


@pytest.fixture(scope="module")
def browser():
    missing = _missing()
    if missing:
        if os.environ.get("LOADS_REQUIRE_BROWSER") == "1":
            pytest.fail(f"LOADS_REQUIRE_BROWSER=1 but {missing}")
        pytest.skip(missing)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        chromium = playwright.chromium.launch(executable_path=str(CHROMIUM), args=FLAGS)
        yield chromium
        chromium.close()


@pytest.fixture(scope="module")
def page_file(tmp_path_factory) -> Path:
    traj = solve_trajectory(load_case(CASE), forces=("crank_pivot", "pin_c"))
    return write_html(traj, tmp_path_factory.mktemp("page"))


def _pixels(png: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=float)


def test_page_renders_plays_and_draws_the_mechanism(browser, page_file: Path) -> None:
    page = browser.new_page(viewport=VIEWPORT)
    errors: list[str] = []
    fetched: list[str] = []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))

    def only_the_file(route) -> None:
        if route.request.url.startswith("file:"):
            route.continue_()
        else:
            fetched.append(route.request.url)
            route.abort()

    page.route("**/*", only_the_file)
    page.goto(page_file.as_uri())
    canvas = page.wait_for_selector(".js-plotly-plot .gl-container canvas", timeout=15_000)
    page.wait_for_timeout(500)
    steps = page.evaluate("document.getElementById('loads-draw').layout.sliders[0].steps.length")
    frames = page.evaluate("document.getElementById('loads-draw')._transitionData._frames.length")
    assert steps == frames == MAX_FRAMES
    assert page.locator(".slider-tick-rect").count() == MAX_FRAMES

    page.get_by_text("Play", exact=True).click()
    page.wait_for_timeout(800)
    page.get_by_text("Pause", exact=True).click()
    active = page.evaluate("document.getElementById('loads-draw').layout.sliders[0].active")
    assert 0 < active < MAX_FRAMES

    shot = _pixels(page.screenshot(path=str(page_file.with_suffix(".png"))))
    scene = _pixels(canvas.screenshot())
    page.close()
    assert errors == [] and fetched == []
    assert shot.std() > 10.0 and scene.std() > 5.0  # neither blank
    reds = np.all(np.abs(scene - FORCE_RGB) < 40, axis=2).sum()
    assert reds > 50, "no force arrow drawn in the WebGL scene"
