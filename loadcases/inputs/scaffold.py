"""Case skeletons: `loads new KIND NAME` copies a commented template of `templates/cases/`.

`blank` is a generic case to start from; each other kind is a load-case family of the
source documents (door lifting, jamming, opening, opened, jettison; solar-array
deployment; rod-end duty cycle). A skeleton is a complete,
runnable case with its mechanism inline, written as `NAME.case.yaml` with `case: NAME`.
Files are never overwritten; the new file appears whole or not at all.
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass
from pathlib import Path

import yaml

from loadcases.foundation.atomic import atomic_write_text

__all__ = [
    "SKELETONS",
    "TEMPLATE_DIR",
    "Skeleton",
    "check_name",
    "skeleton_text",
    "template_path",
    "write_skeleton",
]

TEMPLATE_DIR = Path(__file__).resolve().parents[2] / "templates" / "cases"
CASE_SUFFIX = ".case.yaml"
_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+=,-]*")
_CASE_LINE = re.compile(r"^(case:[ \t]*)(\S+)", re.MULTILINE)


@dataclass(frozen=True)
class Skeleton:
    """A kind of case: its template file (in `TEMPLATE_DIR`) and what it computes."""

    template: str
    summary: str


SKELETONS: dict[str, Skeleton] = {
    "blank": Skeleton(
        "blank.case.yaml",
        "a generic, commented case to start from: one arm on a hinge, "
        "turned by a motion, with its reactions and drive torque",
    ),
    "lifting": Skeleton(
        "lifting.case.yaml",
        "door lifted by its handle: handle torque, "
        "guide and latch-shaft reactions vs latch-shaft rotation",
    ),
    "jamming": Skeleton(
        "jamming.case.yaml",
        "jam in the lifting linkage under the ultimate "
        "handle load: rod forces vs latch-shaft rotation",
    ),
    "opening": Skeleton(
        "opening.case.yaml",
        "door opened by its counterbalance strut in wind: hinge and CB rod forces vs hinge angle",
    ),
    "opened": Skeleton(
        "opened.case.yaml",
        "door open as a staircase under crew loads: hinge, CB rod and wire forces (static)",
    ),
    "jettison": Skeleton(
        "jettison.case.yaml",
        "door thrown open by air loads: hinge forces, "
        "angular rate and acceleration vs hinge angle (dynamic)",
    ),
    "deployment": Skeleton(
        "deployment.case.yaml",
        "spring-driven solar array deployment: "
        "hinge-line angles, rates, spring torques and reactions",
    ),
    "rod-end": Skeleton(
        "rod_end_duty_cycle.case.yaml",
        "flight-control rod-end on a slider-crank actuator duty cycle: rod-end and actuator forces",
    ),
}


def template_path(kind: str) -> Path:
    """The template file of `kind`; ValueError naming the kinds (and the closest one)."""
    skeleton = SKELETONS.get(kind)
    if skeleton is None:
        close = difflib.get_close_matches(kind, list(SKELETONS), n=1)
        hint = f" (did you mean '{close[0]}'?)" if close else ""
        raise ValueError(f"unknown kind '{kind}'{hint}: use one of {', '.join(SKELETONS)}")
    return TEMPLATE_DIR / skeleton.template


def check_name(name: str) -> None:
    """ValueError unless `name` can be both a file name and a case name: letters, digits
    and `_ . + = , -`, starting with a letter or digit, without the `.case.yaml` suffix."""
    if not _NAME.fullmatch(name) or name.endswith(CASE_SUFFIX):
        raise ValueError(
            f"invalid name '{name}': use letters, digits and _ . + = , - "
            "(starting with a letter or digit), without a folder or "
            f"the {CASE_SUFFIX} suffix"
        )


def _yaml_scalar(name: str) -> str:
    """`name` as a YAML scalar that reads back as the same string (quoted if needed)."""
    return name if yaml.safe_load(name) == name else f'"{name}"'


def skeleton_text(kind: str, name: str) -> str:
    """The template of `kind` with its `case:` value set to `name`."""
    check_name(name)
    text = template_path(kind).read_text(encoding="utf-8")
    new_text, count = _CASE_LINE.subn(lambda m: m.group(1) + _yaml_scalar(name), text, count=1)
    if count != 1:
        raise ValueError(f"{template_path(kind)}: template without a top-level 'case:' line")
    return new_text


def write_skeleton(kind: str, name: str, out_dir: Path) -> Path:
    """Write `out_dir/NAME.case.yaml` from the template of `kind`; return its path.

    Raises FileExistsError if the file exists (it is never overwritten, even when another
    process creates it meanwhile), ValueError for an unknown kind or an invalid name.
    """
    text = skeleton_text(kind, name)
    target = Path(out_dir) / f"{name}{CASE_SUFFIX}"
    if target.exists():
        raise FileExistsError(f"{target} exists: not overwritten (choose another NAME or -o)")
    try:
        return atomic_write_text(target, text, overwrite=False)
    except FileExistsError:
        raise FileExistsError(f"{target} exists: not overwritten") from None
