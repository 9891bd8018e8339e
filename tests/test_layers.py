"""The layers hold: cli -> loadcases -> mechlib, and inside loadcases each sub-package imports
only from the layers below it (no cycles, no back-imports between siblings). Read from the
source (every import statement, also those inside functions), not from what happens to be
imported at run time."""

from __future__ import annotations

import ast
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# Lowest first: a part may import from the layers below its own, never from its own layer
# (siblings) or above. `loadcases/__init__.py` is the public API and names everything.
LAYERS: tuple[frozenset[str], ...] = tuple(
    frozenset(layer.split())
    for layer in (
        "clip unit_table cache_env atomic",  # input quoted in messages (at most 80
        # characters); the unit conversions pint made before; the folder named for every
        # cache; files written whole
        "diagnostics units limits engine_hash interrupts process_settings parse_cache",
        # problems as data; quantities; input limits; the engine's source hash; signals; a
        # solving process's BLAS threads and heap; parsed YAML trees
        "source expressions flexible",  # YAML with positions; the expression language;
        # stiffness and mass files of flexible components (readers, reduction cache)
        "schema",  # pydantic models of the files
        "checks",  # semantic checks of the models
        "inputs results",  # files -> validated models; the files of one run
        "build",  # a case -> a mechlib model
        "run report draw",  # one case end to end; reports over saved runs; pictures
        "sets studies",  # sets as campaigns; studies over many solutions of a case
        "warmup",  # `python -m loadcases.warmup`
    )
)
LAYER_OF = {part: rank for rank, layer in enumerate(LAYERS) for part in layer}
MECHLIB_NEVER = ("loadcases", "cli", "yaml", "pydantic", "typer", "openpyxl", "pint")


def imports(path: Path) -> Iterator[tuple[int, str]]:
    """(line, absolute module name) of every import in the file, relative ones resolved."""
    package = ".".join(path.relative_to(ROOT).with_suffix("").parts[:-1])
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            yield from ((node.lineno, alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[: len(parts) - node.level + 1] + ([base] if base else []))
            if base == "loadcases":  # `from loadcases import x`: the module x
                yield from ((node.lineno, f"loadcases.{alias.name}") for alias in node.names)
            else:
                yield node.lineno, base


def part_of(module: str) -> str:
    """`loadcases.report.envelope` -> `report`; `loadcases.run` -> `run`."""
    return module.split(".")[1]


def test_every_part_of_loadcases_has_a_layer() -> None:
    parts = {
        p.stem if p.is_file() else p.name
        for p in (ROOT / "loadcases").iterdir()
        if (p.suffix == ".py" or (p / "__init__.py").is_file()) and p.name != "__init__.py"
    }
    assert parts == set(LAYER_OF), "place new parts of loadcases/ in LAYERS (and in the docs)"


def test_loadcases_imports_only_lower_layers() -> None:
    wrong = []
    for path in sorted((ROOT / "loadcases").rglob("*.py")):
        if path == ROOT / "loadcases" / "__init__.py":
            continue
        source = part_of(".".join(path.relative_to(ROOT).with_suffix("").parts))
        for line, module in imports(path):
            where = f"{path.relative_to(ROOT)}:{line}: {module}"
            if module.split(".")[0] in ("cli", "typer"):
                wrong.append(f"{where} (the CLI is above loadcases)")
            elif module.startswith("loadcases.") and part_of(module) != source:
                if module.count(".") == 1 and part_of(module) not in LAYER_OF:
                    wrong.append(f"{where} (the public API: import from the module)")
                elif LAYER_OF[part_of(module)] >= LAYER_OF[source]:
                    wrong.append(f"{where} ({source} is not above {part_of(module)})")
    assert not wrong, "\n".join(wrong)


def test_mechlib_is_pure() -> None:
    wrong = [
        f"{path.relative_to(ROOT)}:{line}: {module}"
        for path in sorted((ROOT / "mechlib").rglob("*.py"))
        for line, module in imports(path)
        if module.split(".")[0] in MECHLIB_NEVER
    ]
    assert not wrong, "\n".join(wrong)


@pytest.mark.parametrize("module", ["loadcases", "cli.app"])
def test_import_is_light(module: str) -> None:
    """`import loadcases` (the API) and the CLI (`loads --help`) load no solver, plotting,
    Excel or pandas module: each is imported where it is needed (of `mechlib`, only its
    lazy package and `mechlib.core.lazy`)."""
    code = (
        f"import sys, {module}; print(sorted(({{m.split('.')[0] for m in sys.modules}} & "
        "{'matplotlib', 'openpyxl', 'pandas', 'numba', 'scipy'}) | "
        "({m for m in sys.modules if m.startswith('mechlib')} - {'mechlib', 'mechlib.core.lazy'})))"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True
    )
    assert result.stdout.strip() == "[]", result.stdout
