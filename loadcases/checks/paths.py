"""Names and paths that become files: case and set names (result files, `/` makes
sub-folders) and a set's `report.output` stay inside the output folder; `report.template`
is an existing file given relative to the set file."""

from __future__ import annotations

from pathlib import Path, PurePosixPath, PureWindowsPath

from loadcases.foundation.clip import clip, describe_character, hidden_character
from loadcases.foundation.diagnostics import Diagnostic
from loadcases.yamlfiles.source import Locator

__all__ = [
    "FORMULA_STARTS",
    "MAX_NAME_BYTES",
    "check_name",
    "check_report_paths",
    "name_problem",
    "path_problem",
]

MAX_NAME_BYTES = 200  # room for a sweep's `[p=v]`, suffixes and the 255-byte OS limit
FORMULA_STARTS = "=+-@"  # a spreadsheet reads text starting with these as a formula


def path_problem(text: str) -> str | None:
    """Why a relative path `a/b.ext` cannot be used inside the output folder, or None."""
    if PurePosixPath(text).is_absolute() or PureWindowsPath(text).anchor:
        return "an absolute path"
    bad = hidden_character(text)
    if bad is not None:
        return describe_character(bad)
    if "\\" in text:
        return "a backslash (use '/' for sub-folders)"
    parts = text.split("/")
    if ".." in parts:
        return "it leaves the output folder ('..')"
    if "" in parts[:-1] or not parts[-1]:
        return "an empty folder name ('//')" if "" in parts[1:-1] else "an empty file name"
    size = len(text.encode("utf-8"))
    return f"longer than {MAX_NAME_BYTES} bytes ({size})" if size > MAX_NAME_BYTES else None


def name_problem(name: str) -> str | None:
    """Why a case or set name cannot name result files, or None."""
    problem = path_problem(name)
    if problem is None and name[:1] in FORMULA_STARTS:
        problem = f"it starts with '{name[0]}' (a formula in a spreadsheet)"
    return problem


def check_name(at: Locator, key: str, name: str) -> list[Diagnostic]:
    """The diagnostic of a case or set name that cannot be a result file name."""
    problem = name_problem(name)
    if problem is None:
        return []
    return [
        at.diagnostic(
            (key,),
            f"cannot be a result file name: {problem}",
            hint="use letters, digits, '-', '_', '.', and '/' for sub-folders",
        )
    ]


def check_report_paths(at: Locator, output: str, template: str | None) -> list[Diagnostic]:
    """`report.output` inside the output folder; `report.template` an existing file
    relative to the set file."""
    found = []
    problem = path_problem(output)
    if problem == "an absolute path":
        problem += "; give a name relative to the output folder"
    if problem is not None:
        found.append(
            at.diagnostic(
                ("report", "output"), f"'{clip(output)}' cannot be the workbook's name: {problem}"
            )
        )
    if template is None:
        return found
    if PurePosixPath(template).is_absolute() or PureWindowsPath(template).anchor:
        found.append(
            at.diagnostic(
                ("report", "template"),
                f"'{clip(template)}' is an absolute path; give it relative to the set file",
            )
        )
    elif not (Path(at.tree.file).parent / template).is_file():
        found.append(
            at.diagnostic(
                ("report", "template"),
                f"no such file '{clip(template)}' (relative to the set file)",
            )
        )
    return found
