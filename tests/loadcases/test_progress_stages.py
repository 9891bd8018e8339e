"""The progress of a run file (loadcases.run.run_file): the run, then each further solve of
its accuracy estimate as its stage, where the callback can name stages; a plain callback
follows the run alone."""

from __future__ import annotations

from pathlib import Path

from loadcases.run import run_file
from loadcases.run.global_error import COMPANION_STAGE

CASE = Path(__file__).resolve().parents[2] / "loadcases/library/verification/pendulum.case.yaml"


class Recorder:
    """A progress callback that names stages, as the command's bar does."""

    def __init__(self) -> None:
        self.stage = ""
        self.calls: list[tuple[str, float, float]] = []

    def staged(self, stage: str) -> Recorder:
        self.stage = stage
        return self

    def __call__(self, t: float, t_end: float) -> None:
        self.calls.append((self.stage, t, t_end))


def test_the_companion_run_is_reported_as_its_stage(tmp_path: Path) -> None:
    """The pendulum over 4 s: its run's progress to 4 s, then its companion's, named, to
    4 s again (a long run's bar no longer sits at 100 % while the companion runs)."""
    recorder = Recorder()
    [outcome] = run_file(CASE, output_dir=tmp_path, progress=recorder)
    assert outcome.solution.status == "ok"
    stages = [stage for stage, _, _ in recorder.calls]
    assert stages == sorted(stages, key=["", COMPANION_STAGE].index)  # run first, then companion
    for stage in ("", COMPANION_STAGE):
        times = [t for s, t, _ in recorder.calls if s == stage]
        assert times and times == sorted(times) and times[-1] == 4.0
        assert all(end == 4.0 for s, _, end in recorder.calls if s == stage)


def test_a_plain_callback_follows_the_run_alone(tmp_path: Path) -> None:
    """A callback without `staged` (a function) is called for the run only: its times
    rise once to the end, never back to the start for the companion."""
    times: list[float] = []
    run_file(CASE, output_dir=tmp_path, progress=lambda t, end: times.append(t))
    assert times and times == sorted(times) and times[-1] == 4.0
