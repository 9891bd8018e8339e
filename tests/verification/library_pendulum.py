"""The verification library's pendulum run with another end, output interval and analysis
lines: the case the global-error and sampling tests edit."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from loadcases.inputs.loader import load_case
from loadcases.run import run_case

LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library" / "verification"


def run_pendulum(folder: Path, end: float, step: float, analysis_lines: str = "") -> Any:
    """The outcome of `pendulum.case.yaml` over `end` s at `step` s outputs, with
    `analysis_lines` added to its analysis, written to and run in `folder`."""
    text = (LIBRARY / "pendulum.case.yaml").read_text(encoding="utf-8")
    text = text.replace("end: 4.0 ", f"end: {end} ").replace("step: 0.001 ", f"step: {step} ")
    text = text.replace("  type: dynamic\n", "  type: dynamic\n" + analysis_lines)
    path = folder / "pendulum.case.yaml"
    path.write_text(text, encoding="utf-8")
    return run_case(load_case(path))
