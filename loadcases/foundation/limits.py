"""Documented limits of the input (docs/user-guide.md "Input rules"): beyond them `loads` stops with
an input error (exit 2) instead of hanging or running out of memory."""

from __future__ import annotations

import glob
import math
import os
from collections.abc import Sequence
from pathlib import Path

__all__ = [
    "MAX_EXPRESSION_CHARS",
    "MAX_EXPRESSION_DEPTH",
    "MAX_FE_DOF",
    "MAX_FE_FILE_BYTES",
    "MAX_FE_TERMS",
    "MAX_HARDPOINTS",
    "MAX_HARDPOINT_BYTES",
    "MAX_NODE_ID",
    "MAX_QUANTITY_CHARS",
    "MAX_REPEATS",
    "MAX_ROWS",
    "MAX_RUNS",
    "MAX_YAML_DEPTH",
    "MAX_YAML_VALUES",
    "MIN_TOLERANCE",
    "capped_jobs",
    "local_path_problem",
    "pattern_problem",
    "rows_problem",
    "runs_problem",
]

MAX_ROWS = 10_000_000  # output rows of one run (end / step): ~1 GB of CSV per column set
MAX_RUNS = 100_000  # runs of one set (sweep x zip)
# an integrator's tolerance: below it the error test divides by a scale at round-off (an
# absolute tolerance of 1e-300 made Radau's matrix infinite, an internal error)
MIN_TOLERANCE = 1e-14
MAX_REPEATS = 100  # runs of one setting in `loads accuracy` (its CPU time is their median)
MAX_YAML_VALUES = 1_000_000  # values of one YAML file once its aliases are expanded
MAX_YAML_DEPTH = 100  # nesting of mappings and lists in one YAML file
MAX_HARDPOINTS = 100_000  # points of one hardpoint CSV file
MAX_HARDPOINT_BYTES = 20_000_000  # size of one hardpoint CSV file (~200 bytes a point)
MAX_EXPRESSION_CHARS = 10_000  # characters of one expression (the library's longest: 331)
# levels of one expression: parentheses, calls, unary operators and each operator of a
# chain such as `a + b + c` (the library's deepest: 12); its derivatives stay well inside
# Python's recursion limit
MAX_EXPRESSION_DEPTH = 64
# imported flexible components (docs/flexible-bodies-import.md "Limits"): checked against a
# file's header before anything is allocated
MAX_FE_DOF = 1_000_000  # rows (and columns) of one stiffness or mass matrix
MAX_FE_TERMS = 50_000_000  # stored terms of one matrix (about 1.2 GB once read)
MAX_FE_FILE_BYTES = 2_000_000_000  # size of one matrix, bulk-data or npz file (unpacked)
MAX_NODE_ID = 2_147_483_647  # node and grid ids are 1 to this (NASTRAN's 32-bit integers)
# m: a node of an imported component at most this far from its file's origin (1000 km; the
# rigid-body checks square coordinates times masses, which overflow far beyond)
MAX_NODE_DISTANCE = 1e6
MAX_QUANTITY_CHARS = 100  # characters of one quantity text such as "12 N*m/rad"


def rows_problem(end: float, step: float) -> str | None:
    """Why `end / step` output rows are too many, or None."""
    rows = end / step
    if rows <= MAX_ROWS:
        return None
    return (
        f"end / step gives {rows:.3g} output rows; at most {MAX_ROWS:,} (take a longer "
        "step or a shorter end)"
    )


def runs_problem(sweep: Sequence[Sequence[float]], zip_length: int) -> str | None:
    """Why the sweep lists (cartesian product) times the zip rows are too many runs."""
    runs = math.prod(len(values) for values in sweep) * max(zip_length, 1)
    if runs <= MAX_RUNS:
        return None
    return f"the sweep gives {runs:,} runs; a set has at most {MAX_RUNS:,}"


def pattern_problem(pattern: str) -> str | None:
    """Why a `cases:` glob pattern could reach outside the set file's folder tree."""
    if not glob.has_magic(pattern):
        return None
    parts = pattern.replace("\\", "/").split("/")
    if os.path.isabs(pattern) or ".." in parts:
        return (
            f"the pattern '{pattern[:80]}' leaves the set file's folder; patterns "
            "stay inside it (name files outside it one by one)"
        )
    return None


def local_path_problem(path: str, folder: Path, owner: str) -> str | None:
    """Why a file named in an input file (relative to `folder`, the folder of `owner`)
    could be read from outside that folder tree, as `pattern_problem` keeps a set's
    `cases:` inside the set file's folder: absolute, `..`, or a link that leads out."""
    parts = path.replace("\\", "/").split("/")
    leaves = f"'{path[:80]}' leaves the folder of {owner}; files it names stay inside it"
    if os.path.isabs(path) or ".." in parts or path.startswith("~"):
        return leaves
    root = os.path.realpath(folder)
    if os.path.commonpath([root, os.path.realpath(folder / path)]) != root:
        return leaves + " (a link leads out)"
    return None


def capped_jobs(jobs: int | None) -> tuple[int | None, str | None]:
    """`jobs` capped at the number of cores, with a warning when it was above."""
    cores = os.cpu_count() or 1
    if jobs is None or jobs <= cores:
        return jobs, None
    return cores, f"--jobs {jobs} is more than the {cores} cores of this machine: {cores} used"
