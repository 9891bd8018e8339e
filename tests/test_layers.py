"""The layers hold: cli -> loadcases -> mechlib; inside loadcases and inside mechlib each
sub-package imports only from the layers below it (no back-imports between siblings); and no
module of the three takes part in an import cycle. Read from the source (every import
statement, also those inside functions), not from what happens to be imported at run time.
Imports under `if TYPE_CHECKING:` are annotations only, never executed: they are left out."""

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
        "foundation",  # problems as data, input limits and quoting, quantities, files
        # written whole, cache folders, the engine's source hash, signals, a solving
        # process's settings
        "yamlfiles expressions flexible",  # YAML with positions (and its parse cache); the
        # expression language; stiffness and mass files of flexible components (readers,
        # reduction cache)
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

# mechlib's packages, lowest first, by the same rule (docs/architecture.md, "mechlib").
MECHLIB_LAYERS: tuple[frozenset[str], ...] = tuple(
    frozenset(layer.split())
    for layer in (
        "core",  # outcome, counters, rotations, the kernel decorator: imports nothing of mechlib
        "model",  # what the user builds: bodies, joints, tables, curves, analysis settings
        "linalg",  # factors that name their singularity, flat LU, LAPACK, rank
        "kinematics",  # one state: compiled primitives, constraint rows, reactions, the view
        "elements flexible",  # force elements (contact, hydraulics); flexible bodies
        "system",  # the mechanism compiled to arrays, planar reduction, saddle factors
        "outputs",  # requests evaluated on a trajectory, the energy balance
        "checks",  # redundancy and degrees of freedom by joint, near-singular positions
        "solvers",  # the contract, march, events, the analyses and `solve`
    )
)
MECHLIB_LAYER_OF = {part: rank for rank, layer in enumerate(MECHLIB_LAYERS) for part in layer}
MECHLIB_NEVER = ("loadcases", "cli", "yaml", "pydantic", "typer", "openpyxl", "pint")


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    """ids of the nodes under `if TYPE_CHECKING:` (never executed)."""
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skip.update(id(inner) for child in node.body for inner in ast.walk(child))
    return skip


def _is_module(name: str) -> bool:
    path = ROOT.joinpath(*name.split("."))
    return path.with_suffix(".py").is_file() or (path / "__init__.py").is_file()


def imports(path: Path) -> Iterator[tuple[int, str]]:
    """(line, absolute module name) of every import in the file that runs, relative ones
    resolved; `from package import module` names the module."""
    package = ".".join(path.relative_to(ROOT).with_suffix("").parts[:-1])
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skip = _type_checking_nodes(tree)
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            yield from ((node.lineno, alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")
                base = ".".join(up[: len(up) - node.level + 1] + ([base] if base else []))
            for alias in node.names:
                name = f"{base}.{alias.name}"
                # `from loadcases import x`: x by name, so that the API rule below sees it
                yield node.lineno, name if _is_module(name) or base == "loadcases" else base


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
        if (ROOT / "loadcases" / "library") in path.parents:
            continue  # the library's data folders: scripts that use the package from above
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
    lazy package, `mechlib.core` and `mechlib.core.lazy`)."""
    code = (
        f"import sys, {module}; print(sorted(({{m.split('.')[0] for m in sys.modules}} & "
        "{'matplotlib', 'openpyxl', 'pandas', 'numba', 'scipy'}) | "
        "({m for m in sys.modules if m.startswith('mechlib')} - "
        "{'mechlib', 'mechlib.core', 'mechlib.core.lazy'})))"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True
    )
    assert result.stdout.strip() == "[]", result.stdout


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def test_mechlib_is_packages_only() -> None:
    """`ls mechlib/*.py` lists `__init__.py` alone: every module lives in a package by job."""
    assert sorted(p.name for p in (ROOT / "mechlib").glob("*.py")) == ["__init__.py"]


def test_every_package_of_mechlib_has_a_layer() -> None:
    packages = {p.name for p in (ROOT / "mechlib").iterdir() if (p / "__init__.py").is_file()}
    assert packages == set(MECHLIB_LAYER_OF), "place new packages of mechlib/ in MECHLIB_LAYERS"


def test_mechlib_imports_only_lower_layers() -> None:
    wrong = []
    for path in sorted((ROOT / "mechlib").rglob("*.py")):
        if path.parent == ROOT / "mechlib":
            continue  # the package's own __init__: the public names, imported lazily
        source = path.relative_to(ROOT).parts[1]
        for line, module in imports(path):
            parts = module.split(".")
            if parts[0] != "mechlib" or len(parts) < 2 or parts[1] == source:
                continue
            if parts[1] not in MECHLIB_LAYER_OF:
                wrong.append(f"{path.relative_to(ROOT)}:{line}: {module} (import from the module)")
            elif MECHLIB_LAYER_OF[parts[1]] >= MECHLIB_LAYER_OF[source]:
                wrong.append(f"{path.relative_to(ROOT)}:{line}: {source} is not above {parts[1]}")
    assert not wrong, "\n".join(wrong)


def import_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each sorted:
    every module of one imports, through the others, itself."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.get(child, ())))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    cycles.append(sorted(component))
    return cycles


def test_import_cycles_are_found() -> None:
    """The cycle finder itself: a ring of three and a pair are found, a chain is not."""
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a", "d"}, "d": set(), "e": {"f"}, "f": {"e"}}
    assert sorted(import_cycles(graph)) == [["a", "b", "c"], ["e", "f"]]
    assert import_cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []


def test_no_import_cycles() -> None:
    """No module of mechlib, loadcases or cli imports itself through others (imports inside
    functions included): each can be read, tested and changed without its importers."""
    paths = [p for top in ("mechlib", "loadcases", "cli") for p in (ROOT / top).rglob("*.py")]
    modules = {module_name(p): p for p in paths}
    graph = {
        name: {m for _, m in imports(path) if m in modules and m != name}
        for name, path in modules.items()
    }
    cycles = import_cycles(graph)
    assert not cycles, "import cycles:\n" + "\n".join(" <-> ".join(c) for c in cycles)
