"""Run case files end to end: load, build, check, solve, write results."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from pathlib import Path

import mechlib as ml
from loadcases.build.model import BuiltRun, build_mechanism, build_run
from loadcases.build.precheck import case_problems, model_diagnostics
from loadcases.build.torque_margin import plan_torque_margin
from loadcases.flexible.cache import caching_under
from loadcases.foundation import interrupts
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.foundation.process_settings import freeze_heap, one_blas_thread
from loadcases.inputs.kinds import file_kind
from loadcases.inputs.loader import CaseFile, load_case, load_mechanism
from loadcases.inputs.overrides import Override, labels, pairs
from loadcases.inputs.run_identity import run_name
from loadcases.results.files import ResultsNotWritten, write_results
from loadcases.results.outcome import RunOutcome
from loadcases.run.beside import beside_by_default
from loadcases.run.global_error import AccuracyEstimate, accuracy_aim, solve_to_accuracy

__all__ = ["check_case_file", "check_mechanism_file", "run_case", "run_file", "staged"]

Progress = Callable[[float, float], None]


def run_case(
    cf: CaseFile,
    *,
    progress: Progress | None = None,
    abscissa: bool = False,
    name: str | None = None,
    beside: bool = False,
) -> RunOutcome:
    """Solve one loaded case; a solver failure gives a failed outcome with what was computed.

    `beside`: a dynamic run's accuracy companion solved beside it, in a second thread
    (loadcases.run.beside: the same estimate, in less wall time where a core is free).

    `abscissa` adds the case's `abscissa:` expression as column `abscissa.value` (runs of a
    set); `name` names the run (default: the case name, with its `--set` overrides as in
    `CASE[length=1.5]`). Raises InputError for what cannot
    be built or is not well posed (redundant joints, wrong degrees of freedom), with the
    joints named.
    """
    one_blas_thread()
    built = build_run(cf, abscissa=abscissa)
    margin = plan_torque_margin(cf, built)
    checks: dict = {}
    try:
        solution, estimate = _solve(cf, built, progress, beside)
    except ml.ModelError as error:
        raise InputError(model_diagnostics(cf, error)) from None
    # the accepted steps' end times are the accuracy companion's grid and nothing else's:
    # dropped once it has run (A01 over 2000 s: 315k floats a run sent back from a worker)
    solution = dataclasses.replace(
        solution, stats=dataclasses.replace(solution.stats, step_ends=[])
    )
    if estimate is not None:
        checks["accuracy"] = estimate.summary()
        solution = dataclasses.replace(solution, warnings=[*solution.warnings, *estimate.warnings])
    if margin is not None:
        solution, checks["torque_margin"], notes = margin.apply(solution)
        # notes on the results (a failed margin), beside the solver's warnings
        solution = dataclasses.replace(solution, warnings=[*solution.warnings, *notes])
        built.column_units.update(margin.units())
    freeze_heap()
    return RunOutcome(
        name=name or run_name(cf.case.case, pairs(cf.what_if), labels(cf.what_if)),
        case_file=Path(cf.path),
        analysis=built.analysis.name,
        solution=solution,
        input_sha256=cf.input_sha256,
        column_units=built.column_units,
        request_kinds=built.request_kinds,
        warnings=built.warnings,
        parameters=dict(cf.parameters),
        overrides=dict(pairs(cf.what_if)),
        checks=checks,
        level=cf.case.level,
    )


def _solve(
    cf: CaseFile, built: BuiltRun, progress: Progress | None, beside: bool = False
) -> tuple[ml.Solution, AccuracyEstimate | None]:
    """The case's solution and, for a dynamic analysis, its global error estimate (with the
    steps tightened to meet the target when the case sets `accuracy` and no tolerance).
    `progress` follows the run, then each further run as its stage (`staged`)."""

    def solve(analysis, checks: bool = True, stage: str = "", quiet: bool = False) -> ml.Solution:
        follow = None if quiet else staged(progress, stage)
        return built.solve(analysis, progress=follow, checks=checks)

    accuracy = cf.case.analysis.accuracy
    if not isinstance(built.analysis, ml.Dynamic) or accuracy == "off":
        return solve(built.analysis), None
    aim = accuracy_aim(accuracy, cf.case.analysis.tolerance)
    return solve_to_accuracy(
        solve,
        built.analysis,
        aim.target,
        budget=aim.budget,
        measure=aim.measure,
        untightened=aim.untightened,
        beside=beside,
    )


def staged(progress: Progress | None, stage: str) -> Progress | None:
    """The progress callback of a solve of the run's `stage` (loadcases.run.global_error.
    Solver: "" for the run itself): the callback's own `staged(stage)` where it has one
    (the command's bar names the stage: a long run's companion or tighter runs would
    otherwise sit at 100 %), else none: a plain callback follows the run alone."""
    if not stage or progress is None:
        return progress
    made = getattr(progress, "staged", None)
    return made(stage) if callable(made) else None


def run_file(
    path: Path | str,
    *,
    output_dir: Path | str,
    xlsx: bool = False,
    progress: Progress | None = None,
    what_if: Sequence[Override] = (),
    beside: bool | None = None,
) -> list[RunOutcome]:
    """Run a case file and write its results into `output_dir` (SPEC section 3); `what_if`
    (`--set`) overrides parameters and names the run `CASE[name=value]`. Files that cannot
    be written (disk full, permissions): none is left and the outcome's `unwritten` says
    which are missing (the run failed). `beside`: the accuracy companion solved beside the
    run (`run_case`; None: where a second core is free, loadcases.run.beside)."""
    if file_kind(path) == "mechanism":
        raise ValueError(f"{path} is a mechanism file: use check_mechanism_file")
    cf = load_case(path, what_if=what_if)
    with caching_under(output_dir):
        if beside is None:
            beside = beside_by_default()
        outcome = run_case(cf, progress=progress, beside=beside)
    try:
        with interrupts.wrap_up():  # a signal now: the finished run's files first
            write_results(outcome, Path(output_dir), xlsx=xlsx)
    except ResultsNotWritten as error:  # the run failed: it delivers no files
        outcome.unwritten = str(error)
    return [outcome]


def check_mechanism_file(path: Path | str) -> list[str]:
    """Lines describing a mechanism file: bodies, equations, degrees of freedom, redundancy
    (`loads run` on a mechanism checks it; a mechanism alone is not a load case)."""
    mf = load_mechanism(path)
    mechanism = build_mechanism(mf)
    check = ml.inspect_mechanism(mechanism)
    kind = "mechanism" if mechanism.plane is None else f"planar mechanism ({mechanism.plane})"
    lines = [
        f"{Path(path).name}: {kind} with {check.bodies} bodies, {check.equations} "
        f"constraint equations, {check.degrees_of_freedom} "
        f"degree{'' if check.degrees_of_freedom == 1 else 's'} of freedom"
    ]
    if not check.assembled:
        lines.append(
            "  the design position does not satisfy every joint (assembly will move the bodies)"
        )
    lines += [
        f"  redundant: {r} (a case must drop them: analysis.redundant: drop)"
        for r in check.redundant
    ]
    return lines


def check_case_file(path: Path | str) -> list[Diagnostic]:
    """Everything `loads run` would refuse about a case file, without solving
    (`loadcases.build.precheck.case_problems`)."""
    try:
        return case_problems(load_case(path))
    except InputError as error:
        return list(error.diagnostics)
