"""The name and the reuse key of one run: its case, the parameter values that set it apart
(a set's sweep, a `--set` override) and the engine version."""

from __future__ import annotations

import hashlib
import json

__all__ = ["Pairs", "run_hash", "run_name"]

Pairs = tuple[tuple[str, float], ...]


def run_name(family: str, swept: Pairs) -> str:
    """`CASE[p1=v1,p2=v2]` with values `%g` (SI), or `CASE` when nothing is swept."""
    if not swept:
        return family
    return f"{family}[{','.join(f'{name}={value:g}' for name, value in swept)}]"


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
