"""Semantic checks after the schema: every problem with its position and a fix hint."""

from loadcases.checks.case import check_case, check_case_alone, resolve_initial
from loadcases.checks.mechanism import check_mechanism, mechanism_names
from loadcases.checks.sets import check_set, check_set_cases

__all__ = [
    "check_case",
    "check_case_alone",
    "check_mechanism",
    "check_set",
    "check_set_cases",
    "mechanism_names",
    "resolve_initial",
]
