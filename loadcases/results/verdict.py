"""The accuracy verdict of a dynamic run as its workbooks show it, read from the summary's
`accuracy` block (`loadcases.run.global_error.AccuracyEstimate.summary`): the target and
the estimates are fractions of each request's peak, `met` is null when nothing was
estimated (the companion failed or was interrupted)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["AccuracyVerdict", "accuracy_rows"]

_ESTIMATE_HEADER = ("request", "history (of peak)", "peak (of peak)", "sampling (of peak)")
_ESTIMATES = ("history", "peak", "sampling")
_SETTINGS = ("measure", "integrator", "tolerance", "tightenings")  # of the run written


@dataclass(frozen=True)
class AccuracyVerdict:
    """`target` (fraction of each request's peak), `met` (None: not estimated) and
    `outcome` (`met`, or `not met: ` and why) of one run."""

    target: float
    met: bool | None
    outcome: str

    @classmethod
    def of(cls, block: dict[str, Any] | None) -> AccuracyVerdict | None:
        """From a summary's `accuracy` block; None without one (not a dynamic run, or
        `accuracy: off`)."""
        if not block:
            return None
        return cls(float(block["target"]), block.get("met"), str(block.get("outcome", "")))

    @property
    def met_text(self) -> str:
        """`yes`, `no`, or `not estimated`."""
        if self.met is None:
            return "not estimated"
        return "yes" if self.met else "no"


def accuracy_rows(block: dict[str, Any] | None) -> list[list[Any]]:
    """The Summary sheet's lines of a run's accuracy: `accuracy.KEY`, value (and its unit)
    for the verdict and the settings of the run written, a blank line, then one line per
    request under its header (`request`, `history (of peak)`, ...), fractions of the
    request's peak; no lines without an `accuracy` block."""
    verdict = AccuracyVerdict.of(block)
    if verdict is None or block is None:
        return []
    rows: list[list[Any]] = [
        ["accuracy.target", verdict.target, "of each request's peak"],
        ["accuracy.met", verdict.met_text],
        ["accuracy.outcome", verdict.outcome],
    ]
    rows += [[f"accuracy.{key}", block[key]] for key in _SETTINGS if key in block]
    if "cpu_seconds" in block:  # of the companion and the tighter runs
        rows.append(["accuracy.cpu_seconds", block["cpu_seconds"], "s"])
    if block.get("note"):
        rows.append(["accuracy.note", str(block["note"])])
    estimates = block.get("estimate") or {}
    if estimates:
        rows += [[], list(_ESTIMATE_HEADER)]
        rows += [[name, *(e.get(k) for k in _ESTIMATES)] for name, e in estimates.items()]
    return rows
