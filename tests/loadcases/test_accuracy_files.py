"""The files of `loads accuracy` (loadcases.studies.accuracy_files): the work-precision
diagram's tick labels are numbers as written (`1e-03`, `3e-02`), not math text shown as
written (`$\\mathdefault{10^{-2}}$`, which overlapped on a CPU axis of less than a decade),
and every label lies on the canvas; a `$` in the case name stays a dollar sign."""

from __future__ import annotations

from pathlib import Path

import pytest
from matplotlib.axis import Axis
from matplotlib.figure import Figure
from matplotlib.text import Text

from loadcases.studies.accuracy import AccuracyStudy, ColumnError, Setting, SettingResult
from loadcases.studies.accuracy_files import write_accuracy_files


def _result(integrator: str, tolerance: float, cpu: float, error: float) -> SettingResult:
    errors = {"hinge_force.fx": ColumnError(error, error, error)}
    return SettingResult(Setting(integrator, tolerance), "ok", "finished", cpu, {}, errors)


def _study(case: str) -> AccuracyStudy:
    """Two integrators over 0.021-0.041 s of CPU (less than a decade: minor ticks labelled)
    and errors from 4e-6 to 3e-3 of peak."""
    return AccuracyStudy(
        case,
        1e-3,
        [
            _result("generalized-alpha", 1e-4, 0.021, 3e-3),
            _result("generalized-alpha", 1e-6, 0.034, 2e-5),
            _result("radau", 1e-4, 0.025, 1e-3),
            _result("radau", 1e-6, 0.041, 4e-6),
        ],
        {"generalized-alpha": Setting("radau", 1e-8), "radau": Setting("generalized-alpha", 1e-8)},
        [],
        2e-7,
    )


@pytest.fixture
def saved_figure(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Figure:
    """The diagram's figure as `write_accuracy_files` saved it (drawn, laid out)."""
    saved: list[Figure] = []
    original = Figure.savefig

    def keep(figure: Figure, *args: object, **kwargs: object) -> None:
        saved.append(figure)
        original(figure, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", keep)
    write_accuracy_files(_study("pend$2$"), tmp_path)
    assert len(saved) == 1 and (tmp_path / "pend$2$.accuracy.png").stat().st_size > 10_000
    return saved[0]


def _drawn_labels(axis: Axis) -> list[Text]:
    """The tick labels drawn: of the major and minor ticks within the axis's view."""
    low, high = sorted(axis.get_view_interval())
    ticks = [*axis.get_major_ticks(), *axis.get_minor_ticks()]
    return [t.label1 for t in ticks if low <= t.get_loc() <= high and t.label1.get_text()]


def test_tick_labels_are_plain_numbers(saved_figure: Figure) -> None:
    axes = saved_figure.axes[0]
    x = [t.get_text() for t in _drawn_labels(axes.xaxis)]
    y = [t.get_text() for t in _drawn_labels(axes.yaxis)]
    assert x and y
    assert not [text for text in x + y if "$" in text or "mathdefault" in text]
    numbers = {float(text.replace("\N{MINUS SIGN}", "-")) for text in x + y}
    assert {0.03, 0.04} <= numbers  # the CPU axis's minor ticks, 3e-02 and 4e-02
    assert {1e-3, 1e-4, 1e-5} <= numbers
    assert axes.get_title() == "pend$2$: work-precision (labels: tolerance)"  # as written


def test_labels_lie_on_the_canvas(saved_figure: Figure) -> None:
    renderer = saved_figure.canvas.get_renderer()
    canvas = saved_figure.bbox
    axes = saved_figure.axes[0]
    texts = [*_drawn_labels(axes.xaxis), *_drawn_labels(axes.yaxis)]
    for text in [*texts, axes.xaxis.label, axes.yaxis.label, axes.title]:
        box = text.get_window_extent(renderer)
        assert canvas.x0 <= box.x0 and box.x1 <= canvas.x1, text.get_text()
        assert canvas.y0 <= box.y0 and box.y1 <= canvas.y1, text.get_text()
    tight = saved_figure.get_tightbbox(renderer)  # inches
    assert tight.x0 >= 0.0 and tight.y0 >= 0.0
    assert tight.x1 <= saved_figure.get_figwidth() and tight.y1 <= saved_figure.get_figheight()
