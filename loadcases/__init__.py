"""The load-case layer of `loads`: YAML mechanism, case and set files -> runs -> results,
envelopes and workbooks. This is its public API; the sub-packages hold the parts:

- `inputs/` the files (kind, validated models), `schema/`, `checks/`, `expressions/`;
- `build/` a case -> a `mechlib` model; `run` one case end to end; `results/` its files;
- `sets/` sets run as campaigns; `report/` envelopes, margins, plots, workbooks; `draw/`;
- `foundation/` diagnostics, limits, units, caches, signals; `yamlfiles/` YAML with
  positions.

Names are imported when first used (`loadcases.run_case` imports the solver stack,
`loadcases.write_workbook` openpyxl), so `import loadcases` stays quick.
"""

from __future__ import annotations

from loadcases.foundation.diagnostics import Diagnostic, InputError
from mechlib.core.lazy import lazy_names

_WHERE = {
    "loadcases.inputs.kinds": ("FileKind", "file_kind"),
    "loadcases.inputs.loader": (
        "CaseFile",
        "MechanismFile",
        "SetFile",
        "load_case",
        "load_mechanism",
        "load_set",
        "validate_files",
    ),
    "loadcases.inputs.scaffold": ("SKELETONS", "write_skeleton"),
    "loadcases.schema": ("json_schema",),
    "loadcases.build.model": ("BuiltRun", "build_run", "build_mechanism"),
    "loadcases.run": ("run_case", "run_file", "check_case_file", "check_mechanism_file"),
    "loadcases.sets.precheck": ("file_problems",),
    "loadcases.results.outcome": ("RunOutcome",),
    "loadcases.results.files": ("write_results", "read_results"),
    "loadcases.results.saved": ("SavedRun", "load_saved_run"),
    "loadcases.sets.specs": ("RunSpec", "CompiledSet", "load_and_compile_set"),
    "loadcases.sets.executors": ("make_executor",),
    "loadcases.sets.campaign": ("SetResult", "run_set"),
    "loadcases.report.envelope": ("EnvelopeRow", "extract_envelope", "write_envelope_csv"),
    "loadcases.report.margins": ("apply_margins",),
    "loadcases.report.curves": ("EnvelopeCurve", "envelope_curves"),
    "loadcases.report.saved_report": ("SavedReport", "saved_report"),
    "loadcases.report.workbook": ("WorkbookData", "write_workbook"),
    "loadcases.report.plots": ("plot_runs", "write_envelope_plots"),
    "loadcases.draw.trajectory": ("Trajectory", "trajectory_of_file"),
    "loadcases.draw.render": ("write_pngs", "write_animation"),
    "loadcases.draw.page": ("write_html",),
    "loadcases.flexible.read": ("FEImport", "read_fe_model"),
    "loadcases.flexible.neutral": ("write_neutral",),
    "loadcases.flexible.cache": ("cached",),
}
_MODULE_OF = {name: module for module, names in _WHERE.items() for name in names}

__all__ = ["Diagnostic", "InputError", *_MODULE_OF]


__getattr__, __dir__ = lazy_names(__name__, _MODULE_OF, globals(), __all__)
