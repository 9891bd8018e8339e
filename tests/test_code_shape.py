"""The shape the code keeps (DESIGN.md, habit 8): no class of mechlib, loadcases or cli above
300 lines; ruff's C901 (at 15, pyproject.toml) keeps each function's branches in check."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MOST_CLASS_LINES = 300


def test_no_class_above_300_lines() -> None:
    long = [
        f"{path.relative_to(ROOT)}:{node.lineno}: {node.name} ({node.end_lineno - node.lineno + 1})"
        for top in ("mechlib", "loadcases", "cli")
        for path in sorted((ROOT / top).rglob("*.py"))
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
        if isinstance(node, ast.ClassDef)
        and (node.end_lineno or node.lineno) - node.lineno + 1 > MOST_CLASS_LINES
    ]
    assert not long, "split these classes by job:\n" + "\n".join(long)
