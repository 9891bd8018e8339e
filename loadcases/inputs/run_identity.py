"""The name and the reuse key of one run: its case, the parameter values that set it apart
(a set's sweep, a `--set` override) and the engine version.

A run is named `CASE[p1=v1,p2=v2]` (SPEC 3), each value as the set or the option wrote it:
number and unit without spaces (`airspeed=250kt` for `250 kt`), `%g` of a bare number; a
`/` of a unit, which would make a sub-folder of the run's files, reads `_per_`
(`speed=360deg_per_s`).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping

__all__ = ["Labels", "Pairs", "run_hash", "run_name", "value_label"]

Pairs = tuple[tuple[str, float], ...]
# {(parameter, SI value): the value as written}: how a run name shows a value
Labels = Mapping[tuple[str, float], str]


def value_label(written: object) -> str:
    """A value as a run name shows it: `250 kt` -> `250kt`, 1.5 -> `1.5` (%g), `360 deg/s`
    -> `360deg_per_s`."""
    if isinstance(written, (int, float)) and not isinstance(written, bool):
        return f"{written:g}"
    text = "".join(str(written).split())
    try:
        return f"{float(text):g}"  # a bare number written as text (`1e300`)
    except ValueError:
        return text.replace("/", "_per_")


def run_name(family: str, swept: Pairs, labels: Labels | None = None) -> str:
    """`CASE[p1=v1,p2=v2]` with each value as written (`labels`), else `%g` (SI), or `CASE`
    when nothing is swept."""
    if not swept:
        return family
    shown = labels or {}
    values = (shown.get((name, value)) or f"{value:g}" for name, value in swept)
    return f"{family}[{','.join(f'{name}={v}' for (name, _), v in zip(swept, values))}]"


def run_hash(case_sha256: str, parameters: Pairs, version: str) -> str:
    """SHA-256 over the case/mechanism hash, the run's parameters and the engine version."""
    text = json.dumps(
        {
            "input": case_sha256,
            "version": version,
            "parameters": {name: repr(float(v)) for name, v in sorted(parameters)},
        },
        sort_keys=True,
    )
    return hashlib.sha256(text.encode("utf-8")).hexdigest()
