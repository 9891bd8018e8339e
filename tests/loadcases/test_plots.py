"""PNG plots of saved runs and of envelope curves (loadcases.report.plots)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

from loadcases.report import plots
from loadcases.results.files import write_results
from loadcases.results.outcome import RunOutcome
from mechlib.core.outcome import Solution, SolverStats

WIDTH_PX = 1000  # FIG_WIDTH_IN 10 in at DPI 100


def saved_run(tmp_path: Path, name: str, scale: float = 1.0, *, units: bool = True) -> Path:
    """Write a 51-row run with a joint force, a motion torque and a joint angle; its CSV."""
    time = np.linspace(0.0, 1.0, 51)
    angle = 2.0 * time
    channels = {
        "hinge_force.fx": scale * 100.0 * np.cos(angle),
        "hinge_force.fy": scale * 50.0 * np.sin(angle),
        "hinge_force.tz": scale * 3.0 * np.ones_like(time),
        "drive_torque.value": scale * 12.0 * np.sin(3 * angle),
        "crank_angle.value": angle,
    }
    solution = Solution(
        status="ok",
        message="ok",
        analysis="kinematic",
        time=time,
        channels=channels,
        stats=SolverStats(steps=51, cpu_seconds=0.1),
    )
    column_units = (
        {
            "hinge_force.fx": "N",
            "hinge_force.fy": "N",
            "hinge_force.tz": "N*m",
            "drive_torque.value": "N*m",
            "crank_angle.value": "rad",
        }
        if units
        else {}
    )
    outcome = RunOutcome(
        name, Path(f"{name}.case.yaml"), "kinematic", solution, "0" * 64, column_units=column_units
    )
    write_results(outcome, tmp_path / "results", version="test")
    return tmp_path / "results" / f"{name}.csv"


def png_shape(path: Path) -> tuple[int, int]:
    image = imread(path)
    assert image.ndim == 3 and image.shape[2] in (3, 4)
    assert float(np.std(image[..., :3])) > 0.01, f"{path} looks blank"
    return image.shape[0], image.shape[1]


def height_px(panels: int) -> int:
    return round(plots.DPI * plots.figure_height_in(panels))


def test_known_csv_one_png_per_request_with_expected_size(tmp_path: Path) -> None:
    run = plots.load_saved_run(saved_run(tmp_path, "door-a"))
    assert run.name == "door-a" and run.units["hinge_force.tz"] == "N*m"
    written = plots.plot_runs([run.as_run()], out_dir=tmp_path / "png", units=run.units)
    assert [p.name for p in written] == ["hinge_force.png", "drive_torque.png", "crank_angle.png"]
    assert sorted(p.name for p in (tmp_path / "png").iterdir()) == sorted(p.name for p in written)
    # one run: components grouped by unit -> hinge_force has an N and an N*m panel
    assert png_shape(written[0]) == (height_px(2), WIDTH_PX) == (640, 1000)
    assert png_shape(written[1]) == (height_px(1), WIDTH_PX) == (400, 1000)


def test_overlaid_runs_vs_a_column_one_panel_per_component(tmp_path: Path) -> None:
    runs = [
        plots.load_saved_run(saved_run(tmp_path, name, scale)).as_run()
        for name, scale in (("door-a", 1.0), ("door-b", 1.5), ("door-c", -1.0))
    ]
    written = plots.plot_runs(
        runs, ["hinge_force.f*"], x="crank_angle.value", out_dir=tmp_path / "png"
    )
    assert [p.name for p in written] == ["hinge_force-vs-crank_angle.value.png"]
    assert png_shape(written[0]) == (height_px(2), WIDTH_PX)  # fx and fy panels


def test_x_column_is_not_plotted_against_itself(tmp_path: Path) -> None:
    run = plots.load_saved_run(saved_run(tmp_path, "door-a")).as_run()
    written = plots.plot_runs([run], x="crank_angle.value", out_dir=tmp_path / "png")
    assert {p.name for p in written} == {
        "hinge_force-vs-crank_angle.value.png",
        "drive_torque-vs-crank_angle.value.png",
    }


def test_missing_x_column_and_unmatched_pattern_are_errors(tmp_path: Path) -> None:
    run = plots.load_saved_run(saved_run(tmp_path, "door-a")).as_run()
    with pytest.raises(ValueError, match=r"x column 'hinge_angle\.value' is in none"):
        plots.plot_runs([run], x="hinge_angle.value", out_dir=tmp_path)
    with pytest.raises(
        ValueError,
        match=r"no column matches wire_force \(requests: "
        r"hinge_force, drive_torque, crank_angle\)",
    ):
        plots.plot_runs([run], ["wire_force"], out_dir=tmp_path)
    with pytest.raises(ValueError, match="no runs"):
        plots.plot_runs([], out_dir=tmp_path)
    assert not list(tmp_path.glob("*.png"))


def test_select_columns_requests_and_patterns() -> None:
    cols = ["hinge_force.fx", "hinge_force.fy", "hinge_rate.value", "cb_force.value"]
    assert plots.select_columns(cols, None) == cols
    assert plots.select_columns(cols, ["hinge_force"]) == cols[:2]
    assert plots.select_columns(cols, ["hinge_*.f?"]) == cols[:2]
    assert plots.select_columns(cols, ["cb_force", "hinge_rate.value"]) == cols[2:]


@pytest.mark.parametrize(
    ("column", "unit"),
    [
        ("hinge.fx", "N"),
        ("hinge.t", "N*m"),
        ("door_angle.value", "rad"),
        ("hinge_omega.value", "rad/s"),
        ("tip_vel.x", "m/s"),
        ("tip_pos.y", "m"),
        ("drive_torque.value", "N*m"),
        ("time", "s"),
        ("mystery.value", ""),
    ],
)
def test_column_unit_guessed_from_the_name(column: str, unit: str) -> None:
    assert plots.column_unit(column) == unit


def test_column_unit_prefers_the_summary_units() -> None:
    assert plots.column_unit("tip_pos.y", {"tip_pos.y": "m/s"}) == "m/s"


def test_runs_without_summary_units_and_failed_status(tmp_path: Path) -> None:
    csv = saved_run(tmp_path, "bare", units=False)
    summary = csv.with_name("bare.summary.json")
    summary.write_text(summary.read_text().replace('"status": "ok"', '"status": "failed"'))
    run = plots.load_saved_run(summary)  # a summary names its CSV
    assert run.status == "failed" and run.as_run()[0] == "bare (failed)"
    assert plots.find_result_csvs([tmp_path]) == [csv]
    written = plots.plot_runs([run.as_run()], ["drive_torque"], out_dir=tmp_path / "png")
    assert png_shape(written[0]) == (400, WIDTH_PX)


@dataclass
class Curve:
    column: str
    abscissa_name: str
    x: np.ndarray
    upper: np.ndarray
    lower: np.ndarray
    family: str
    unit: str


def test_envelope_plots_from_objects_and_dicts(tmp_path: Path) -> None:
    x = np.linspace(0.0, 1.9, 40)
    curves = [
        Curve("hinge_fwd_force.fy", "angle(hinge_line)", x, 100 + 50 * x, -20 - x, "opening", "N"),
        {
            "column": "cb_rod_force.value",
            "abscissa_name": "angle(hinge_line)",
            "x": x,
            "upper": np.sin(x),
            "lower": np.sin(x) - 1.0,
            "family": "door/open",
            "unit": "N",
        },
    ]
    written = plots.write_envelope_plots(curves, tmp_path / "env")
    assert [p.name for p in written] == [
        "envelope-opening-hinge_fwd_force.fy.png",
        "envelope-door_open-cb_rod_force.value.png",
    ]
    for path in written:
        assert png_shape(path) == (400, WIDTH_PX)
    assert not [p for p in (tmp_path / "env").iterdir() if p.suffix != ".png"]


def test_envelope_plots_carry_nothing_from_the_curve_before(tmp_path: Path) -> None:
    """The envelope figure is drawn again for each curve: a curve's PNG after another curve
    (larger values, a NaN gap, another abscissa) has the same pixels as drawn alone, and a
    curve within +-1e-9 keeps the -1..1 axis after a large one."""
    x = np.linspace(0.0, 1.2, 51)
    big = {"column": "rod.f", "family": "a", "x": x - 5.0, "abscissa_name": "t", "unit": "N"}
    big.update(upper=500.0 * np.sin(3 * x) + 200.0, lower=500.0 * np.sin(3 * x) - 100.0)
    big["upper"][10:15] = np.nan
    small = {"column": "rod.fz", "family": "b", "x": x, "abscissa_name": "angle(latch)"}
    small.update(upper=np.full(51, 1e-12), lower=np.full(51, -1e-12), unit="N")
    gentle = {"column": "tq.t", "family": "c", "x": x, "abscissa_name": "angle(hinge)"}
    gentle.update(upper=np.cos(x), lower=np.cos(x) - 0.5, unit="N*m")
    alone, after = tmp_path / "alone", tmp_path / "after"
    for curve in (small, gentle):
        plots.write_envelope_plots([curve], alone)
    drawn = plots.write_envelope_plots([big, small, gentle], after)
    assert [p.parent for p in drawn] == [after] * 3
    for name in (p.name for p in drawn[1:]):
        assert np.array_equal(imread(alone / name), imread(after / name)), name


@pytest.mark.parametrize(
    "xlim,ylim",
    [((0.0, 1.0), (-35.0, 41.0)), ((0.0, 1.5), (-1.0, 1.0)), ((-3e-3, 7e-3), (2e4, 9e4))],
)
def test_minor_grid_at_matplotlibs_minor_ticks(xlim: tuple, ylim: tuple) -> None:
    """The minor grid drawn as line collections (plots._MinorGrid) lies where matplotlib's
    own minor ticks would (AutoMinorLocator, majors left out): (0, 1) with majors every
    0.2 gives 15 lines at 0.05, 0.1, 0.15, 0.25, ..., 0.95."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from loadcases.report.plots import _style

    fig = Figure()
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    grid = _style(ax)
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    grid.update()
    drawn_x = [segment[0][0] for segment in grid.vertical.get_segments()]
    drawn_y = [segment[0][1] for segment in grid.horizontal.get_segments()]
    ax.minorticks_on()  # matplotlib's own minor ticks, those in view drawn, as the reference

    def shown(axis, limits):
        return [v for v in axis.get_minorticklocs() if limits[0] <= v <= limits[1]]

    np.testing.assert_allclose(drawn_x, shown(ax.xaxis, xlim), rtol=0, atol=1e-12)
    np.testing.assert_allclose(drawn_y, shown(ax.yaxis, ylim), rtol=0, atol=1e-9)
    if xlim == (0.0, 1.0):
        assert len(drawn_x) == 15
        np.testing.assert_allclose(drawn_x[:4], [0.05, 0.1, 0.15, 0.25], atol=1e-12)


def _recorded_pools(monkeypatch, cores: int) -> list[int]:
    """The processes of each pool `campaign._plots` forks, recorded in the list returned,
    on a machine of `cores` cores."""
    from loadcases.sets import campaign

    started: list[int] = []
    real = campaign.ProcessPoolExecutor

    def recording(max_workers: int):
        started.append(max_workers)
        return real(max_workers=max_workers)

    monkeypatch.setattr(campaign, "ProcessPoolExecutor", recording)
    monkeypatch.setattr(campaign.os, "cpu_count", lambda: cores)
    return started


def _sine_curves(plots_count: int, runs: int, rows: int) -> list:
    """Envelope curves of `plots_count` columns (four a family) over `rows` rows, each
    naming `runs` runs."""
    from loadcases.report.curves import EnvelopeCurve

    x = np.linspace(0.0, 1.0, rows)
    curves = []
    for n in range((plots_count + 3) // 4):
        columns = {f"j{c}.fx": np.sin(x + c) * (10 + c) for c in range(min(4, plots_count))}
        curve = EnvelopeCurve(f"fam{n}", "time", "s", x, runs=tuple(map(str, range(runs))))
        curve.upper = {k: v + 1 for k, v in columns.items()}
        curve.lower = {k: v - 1 for k, v in columns.items()}
        curve.units = dict.fromkeys(columns, "N")
        curves.append(curve)
    return curves


@pytest.mark.parametrize(
    ("plots_count", "runs", "cores", "processes"),
    [(4, 1000, 2, 1), (4, 3, 2, 0), (40, 1, 2, 2), (4, 1000, 1, 0), (1, 1000, 2, 0)],
)
def test_envelope_plots_drawn_beside_the_workbook_when_large(
    tmp_path: Path, monkeypatch, plots_count: int, runs: int, cores: int, processes: int
) -> None:
    """A set's envelope plots are drawn by forked processes when they are many, or a few
    of a sweep of many runs, and there is more than one core; else in this process.
    Either way each plot is written, in the curves' order."""
    from loadcases.sets import campaign

    started = _recorded_pools(monkeypatch, cores)
    curves = _sine_curves(plots_count, runs, 200)
    with campaign._plots(curves, tmp_path) as drawn:
        paths = drawn()
    assert started == ([processes] if processes else [])
    assert len(paths) == plots_count and all(p.stat().st_size > 1000 for p in paths)
    chosen = campaign.plot_curves(curves)
    assert [p.stem for p in paths] == [f"envelope-{c['family']}-{c['column']}" for c in chosen]


@pytest.mark.parametrize(("plots_count", "runs", "forked"), [(4, 3, []), (40, 1, [1])])
def test_envelope_plots_drawn_by_the_process_started_before_the_runs(
    tmp_path: Path, monkeypatch, plots_count: int, runs: int, forked: list[int]
) -> None:
    """With the set's plots process (`loadcases.sets.drawing`), it draws every plot of a
    small set too, and its share of many, the others' processes forked as before; each
    plot written, in the curves' order."""
    from loadcases.sets import campaign
    from loadcases.sets.drawing import Drawing

    started = _recorded_pools(monkeypatch, 2)
    curves = _sine_curves(plots_count, runs, 50)
    drawing = Drawing()
    drawing.start()
    try:
        with campaign._plots(curves, tmp_path, drawing.pool) as drawn:
            paths = drawn()
    finally:
        drawing.close()
    assert started == forked
    chosen = campaign.plot_curves(curves)
    assert [p.stem for p in paths] == [f"envelope-{c['family']}-{c['column']}" for c in chosen]
    assert all(p.stat().st_size > 1000 for p in paths)
