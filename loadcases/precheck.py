"""Everything `loads run` refuses, short of solving, in one place: `loads validate` and
`loads run` (of cases, mechanisms and sets) call these same checks, so a file that
validates is never refused by a run, and a run refuses nothing validate let through.

Beyond the schema and name checks of the loader: the model is built (element/joint
compatibility, constant expressions) and its degrees of freedom and redundant equations
are checked against the analysis.
"""
from __future__ import annotations

from pathlib import Path

import mechlib as ml
from loadcases.build import build_mechanism, build_run
from loadcases.diagnostics import Diagnostic, InputError
from loadcases.loader import CaseFile, file_kind, load_case, load_mechanism, validate_files
from loadcases.sets import load_and_compile_set

__all__ = ["case_problems", "set_problems", "file_problems", "model_diagnostics"]


def model_diagnostics(cf: CaseFile, error: ml.ModelError) -> list[Diagnostic]:
    """Place each well-posedness problem at the joint or motion it names."""
    out = []
    for owner, message in error.problems:
        if owner in cf.mechanism.joints:
            kind, key = "mechanism", f"joints.{owner}"
        elif owner in cf.case.motions:
            kind, key = "case", f"motions.{owner}"
        else:
            kind, key = "case", "analysis"
        file, line, col = cf.where(kind, key)
        out.append(Diagnostic(file, line, col, key, message))
    return out


def case_problems(cf: CaseFile, *, abscissa: bool = False) -> list[Diagnostic]:
    """What a run of the loaded case would refuse: the model cannot be built, or has
    degrees of freedom or redundant equations its analysis does not allow."""
    try:
        built = build_run(cf, abscissa=abscissa)
        ml.check_model(ml.System(built.mechanism), built.analysis, redundant=built.redundant)
    except InputError as error:
        return list(error.diagnostics)
    except ml.ModelError as error:
        return model_diagnostics(cf, error)
    return []


def set_problems(cases: list[CaseFile]) -> list[Diagnostic]:
    """case_problems of every case of a set (built with the abscissa a set records)."""
    return [d for cf in cases for d in case_problems(cf, abscissa=True)]


def file_problems(path: str | Path) -> list[Diagnostic]:
    """Every diagnostic of one file of any kind, as `loads validate` prints them."""
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
