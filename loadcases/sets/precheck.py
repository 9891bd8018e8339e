"""`loads validate` of one file of any kind: the loader's schema and name checks, then the
checks `loads run` makes before solving (`loadcases.build.precheck`): a case's model, a
mechanism's build, every case of a set, and each run of a set with its parameter values
(what `loads run` refuses that run for). Nothing is written."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

from loadcases.build.model import build_mechanism
from loadcases.build.precheck import case_problems, set_problems
from loadcases.foundation.cache_env import reading_only
from loadcases.foundation.diagnostics import SHOWN_RUNS, Diagnostic, InputError
from loadcases.inputs.kinds import file_kind, unknown_kind
from loadcases.inputs.loader import load_case, load_mechanism, validate_set
from loadcases.inputs.overrides import Override
from loadcases.sets.specs import CompiledSet, compile_set

__all__ = ["file_problems", "run_input_problems"]


def file_problems(path: str | Path, what_if: Sequence[Override] = ()) -> list[Diagnostic]:
    """Every diagnostic of one file of any kind (errors and warnings), as `loads validate`
    prints them; nothing is written (a flexible body's reduction is not cached). `what_if`
    (`--set`) overrides parameters of a case, or of a set's cases, as `loads run` does."""
    with reading_only():
        return _file_problems(path, what_if)


def _file_problems(path: str | Path, what_if: Sequence[Override]) -> list[Diagnostic]:
    found: list[Diagnostic] = []
    try:
        kind = file_kind(path)
        if kind is None:
            return [unknown_kind(path)]
        if kind == "mechanism":
            mechanism = load_mechanism(path)
            found += mechanism.warnings
            build_mechanism(mechanism)
        elif kind == "case":
            case = load_case(path, what_if=what_if)
            found += case.warnings
            found += case_problems(case)
        else:
            found += _set_file_problems(path, what_if)
    except InputError as error:
        found += error.diagnostics
    return list(dict.fromkeys(found))


def _set_file_problems(path: str | Path, what_if: Sequence[Override]) -> list[Diagnostic]:
    """A set's diagnostics and those of its case files; the run checks of every case once
    the files load without error."""
    set_file, cases, found = validate_set(path)
    if any(d.severity == "error" for d in found):
        return found
    try:
        compiled = compile_set(set_file, cases, what_if=what_if)
    except InputError as error:
        return found + list(error.diagnostics)
    return found + set_problems(list(compiled.cases)) + run_input_problems(compiled)


def run_input_problems(compiled: CompiledSet) -> list[Diagnostic]:
    """The errors a run's case file gets with the run's parameter values, as `loads run`
    refuses that run (a swept accuracy target of 2, a negative tolerance): each once, at its
    key, naming the runs it refuses. A case whose numeric fields take no parameter (only
    expressions do, evaluated when the run is built) is checked as loaded, not again per run."""
    takes = {str(Path(cf.path).resolve()): bool(cf.parameter_refs) for cf in compiled.cases}
    refused: dict[Diagnostic, list[str]] = {}
    for spec in compiled.runs:
        if not takes.get(spec.case_path, True):
            continue
        try:
            load_case(spec.case_path, overrides=dict(spec.parameters))
        except InputError as error:
            for found in error.diagnostics:
                if found.severity == "error":
                    refused.setdefault(found, []).append(spec.name)
    return [
        dataclasses.replace(found, message=f"{found.message}, in {_run_names(names)}")
        for found, names in refused.items()
    ]


def _run_names(names: list[str]) -> str:
    """`run A`, `runs A, B`, or the first SHOWN_RUNS and how many more."""
    shown = ", ".join(names[:SHOWN_RUNS])
    more = f" and {len(names) - SHOWN_RUNS} more" if len(names) > SHOWN_RUNS else ""
    return f"run{'s' if len(names) > 1 else ''} {shown}{more}"
