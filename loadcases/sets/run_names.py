"""How a set names its runs (SPEC 3): each swept value as the set wrote it
(`loadcases.inputs.run_identity.value_label`), and the runs two values would name alike."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from loadcases.foundation.diagnostics import Diagnostic
from loadcases.inputs.loader import SetFile
from loadcases.inputs.run_identity import value_label

if TYPE_CHECKING:
    from loadcases.sets.specs import RunSpec

__all__ = ["name_clashes", "written_values"]


def written_values(set_file: SetFile) -> dict[tuple[str, float], str]:
    """{(parameter, SI value): the value as the set wrote it} of its sweep and zip lists."""
    raw = set_file.locator.data
    found: dict[tuple[str, float], str] = {}
    for section in ("sweep", "zip"):
        written = raw.get(section) if isinstance(raw, dict) else None
        for name, values in getattr(set_file.model, section).items():
            texts = written.get(name) if isinstance(written, dict) else None
            if isinstance(texts, list) and len(texts) == len(values):
                for value, text in zip(values, texts):
                    found.setdefault((name, float(value)), value_label(text))
    return found


def name_clashes(set_file: SetFile, runs: Sequence[RunSpec]) -> list[Diagnostic]:
    """Distinct values that print alike (`%g` of bare numbers) would overwrite each other's
    results."""
    found, seen = [], set()
    for spec in runs:
        if spec.name in seen:
            names = [name for name, _ in spec.swept] or ["cases"]
            section = "sweep" if names[0] in set_file.model.sweep else "zip"
            found.append(
                Diagnostic(
                    *set_file.where((section, names[0])),
                    f"{section}.{names[0]}",
                    f"two runs are both named '{spec.name}'",
                    hint="bare numbers that differ only beyond 6 significant "
                    "digits print alike in run names (%g); space them wider or write them "
                    "with a unit",
                )
            )
        seen.add(spec.name)
    return found
