"""A set's compiled kernels loaded in this process before its pool of workers is forked.

A process loads numba's kernels on its first run: numba imported and each kernel the run
calls read from the disk cache (0.76 s of CPU for the campaign's slider-crank, 26 kernels;
2026-11-29). Each worker of a pool forked before that loads them again; forked after, it
inherits them. So, before the pool starts, this process solves a short copy of the first run
of each case of the set (its analysis cut to its first two output intervals: the same
kernels as the whole run, the campaign's 26) and drops the result: the kernels are loaded
once instead of once a worker (`loads run SET -j 2`: 0.8 s of CPU less). A case whose
analysis cannot be cut so (static, modes, phases, no end or output interval) is not warmed:
its workers load its kernels as before. Nothing is written; a warm run that fails costs its
time only (the real run then reports what is wrong). The envelope error's crest kernel
(mechlib.outputs.crests), which a short copy's three rows never reach, is loaded on a few
rows of a sine (`_warm_crests`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable

from loadcases.foundation import interrupts
from loadcases.inputs.loader import CaseFile, load_case
from loadcases.sets.specs import RunSpec

__all__ = ["WARM_INTERVALS", "short_copy", "warm_kernels"]

WARM_INTERVALS = 2  # output intervals a warm run solves
_TIMED = ("dynamic", "kinematic", "quasi-static")  # the analyses cut by their end time
_CREST_ROWS = 9  # rows of the sine whose crest loads the crest kernel (two rows either side)


def short_copy(cf: CaseFile) -> CaseFile | None:
    """`cf` with its analysis ending after WARM_INTERVALS output intervals (None: an analysis
    not cut so)."""
    case = cf.case
    analysis = case.analysis
    if case.phases or analysis.type not in _TIMED or not analysis.end or not analysis.step:
        return None
    end = min(float(analysis.end), WARM_INTERVALS * float(analysis.step))
    short = analysis.model_copy(update={"end": end})
    return dataclasses.replace(cf, case=case.model_copy(update={"analysis": short}))


def warm_kernels(specs: Iterable[RunSpec]) -> bool:
    """Solve a short copy of the first of `specs` of each case file here, results dropped;
    False when an interrupt came meanwhile (SIGINT, SIGTERM: no run should start)."""
    from loadcases.run import run_case  # the solver: with the first run, not before

    seen: set[str] = set()
    warmed = False
    for spec in specs:
        if spec.case_path in seen:
            continue
        seen.add(spec.case_path)
        try:
            short = short_copy(load_case(spec.case_path, overrides=dict(spec.parameters)))
            status = "" if short is None else run_case(short, abscissa=True).solution.status
            warmed = warmed or short is not None
        except Exception:  # noqa: BLE001  (the real run reports it, with its file and key)
            status = ""
        if status == "interrupted" or interrupts.received() is not None:
            return False
    if warmed:
        _warm_crests()
    return True


def _warm_crests() -> None:
    """Load the crest kernel of the envelope's error estimate, with the argument types a
    run gives it: the extremes of a sine's rows with a crest and a trough inside."""
    import numpy as np

    from loadcases.run.peak_error import extremes_of

    time = np.linspace(0.0, 1.0, _CREST_ROWS)
    extremes_of(time, np.sin(2.0 * np.pi * time)[:, None])
