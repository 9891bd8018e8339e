"""`loads validate` of one file of any kind: the loader's schema and name checks, then the
checks `loads run` makes before solving (`loadcases.build.precheck`): a case's model, a
mechanism's build, every case of a set."""

from __future__ import annotations

from pathlib import Path

from loadcases.build.model import build_mechanism
from loadcases.build.precheck import case_problems, set_problems
from loadcases.diagnostics import Diagnostic, InputError
from loadcases.inputs.kinds import file_kind
from loadcases.inputs.loader import load_case, load_mechanism, validate_files
from loadcases.sets.specs import load_and_compile_set

__all__ = ["file_problems"]


def file_problems(path: str | Path) -> list[Diagnostic]:
    """Every diagnostic of one file of any kind (errors and warnings), as `loads validate`
    prints them."""
    found = validate_files([path])
    if any(d.severity == "error" for d in found):
        return found
    try:
        kind = file_kind(path)
        if kind == "case":
            found += case_problems(load_case(path))
        elif kind == "mechanism":
            build_mechanism(load_mechanism(path))
        elif kind == "set":
            found += set_problems(list(load_and_compile_set(path).cases))
    except InputError as error:
        found += error.diagnostics
    return list(dict.fromkeys(found))
