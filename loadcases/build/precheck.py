"""Everything `loads run` refuses about a case, short of solving, in one place: `loads
validate` and `loads run` (of cases and sets) call these same checks, so a file that
validates is never refused by a run, and a run refuses nothing validate let through.

Beyond the schema and name checks of the loader: the model is built (element/joint
compatibility, constant expressions, the torque-margin block) and its degrees of freedom and
redundant equations are checked against the analysis. The numba kernels run as Python here
(mechlib.core.jit.interpreted): `loads validate` loads no compiler.
"""

from __future__ import annotations

import mechlib as ml
from loadcases.build.model import build_run
from loadcases.build.torque_margin import plan_torque_margin
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.inputs.loader import CaseFile
from mechlib.core.jit import interpreted

__all__ = ["case_problems", "model_diagnostics", "set_problems"]


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
    """What a run of the loaded case would refuse: the model or its torque-margin block
    cannot be built, or the model has degrees of freedom or redundant equations its
    analysis does not allow."""
    try:
        with interpreted():  # a few Jacobians: not worth loading numba for
            built = build_run(cf, abscissa=abscissa)
            plan_torque_margin(cf, built)
            ml.check_model(
                ml.make_system(built.mechanism), built.analysis, redundant=built.redundant
            )
    except InputError as error:
        return list(error.diagnostics)
    except ml.ModelError as error:
        return model_diagnostics(cf, error)
    return []


def set_problems(cases: list[CaseFile]) -> list[Diagnostic]:
    """case_problems of every case of a set (built with the abscissa a set records)."""
    return [d for cf in cases for d in case_problems(cf, abscissa=True)]
