"""Compile a load-case set (`*.set.yaml`, SPEC 1.4) into frozen run specifications.

Rules (also in docs/user-guide.md "Load-case sets: runs, envelope and workbook"):
- The runs of one case file are the combinations of the set's `sweep:` lists (cartesian
  product, first listed parameter varying slowest) times the rows of its `zip:` lists
  (varied together), restricted to the parameters the case uses: those named in an
  expression of the case or of its mechanism. A case that uses no swept parameter runs
  once, under its own name: it would give the same numbers for every value, so running it
  again would only add identical copies to the envelope.
- Set `parameters:` override the case's for every run of a case that has them.
- A run is named `CASE[p1=v1,p2=v2]`: the swept parameters in the order the set file lists
  them (sweep and zip together), each value as the set wrote it (`airspeed=250kt`; a bare
  number `%g`; `loadcases.inputs.run_identity`); a run with no swept parameter is named
  `CASE`.
- `loads run SET --set NAME=VALUE` overrides NAME in every run of a case that has it
  (after the set's `parameters:`); the override names the run after the swept parameters
  when the case uses it (`CASE[p1=v1,NAME=VALUE]`, VALUE as given). A swept parameter
  cannot be overridden.
- The input hash of a run covers the case and mechanism file bytes, every parameter value
  of the run and the engine version: a run is reused only when all of them are unchanged.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from loadcases.build.elements import ELEMENT_EFFECTS
from loadcases.checks.common import unknown
from loadcases.checks.sets import check_set_cases
from loadcases.expressions import ExpressionError, parse
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.inputs.loader import CaseFile, SetFile, load_case, load_set, load_set_cases
from loadcases.inputs.overrides import (
    Override,
    defined_parameters,
    labels,
    override_problems,
    pairs,
)
from loadcases.inputs.reference_tables import check_reference_curves
from loadcases.inputs.run_identity import Labels, Pairs, run_hash, run_name
from loadcases.results.files import package_version
from loadcases.sets.run_names import name_clashes, written_values

__all__ = [
    "CompiledSet",
    "RunSpec",
    "case_of_run",
    "compile_set",
    "load_and_compile_set",
    "run_hash",
    "run_name",
    "swept_order",
    "used_parameters",
]


@dataclass(frozen=True)
class RunSpec:
    """One run of a set, ready to be solved anywhere (picklable, no solver objects).

    `parameters` are every parameter value of the run (SI); `swept` the swept ones that
    name it; `overrides` the `--set` values among `parameters` (those the case uses name
    the run too, after the swept ones).
    """

    name: str
    family: str
    case_path: str
    parameters: Pairs
    swept: Pairs
    input_sha256: str
    overrides: Pairs = ()


@dataclass(frozen=True)
class CompiledSet:
    """A set with its runs, in order (case files as listed, then sweep order)."""

    set_file: SetFile
    cases: tuple[CaseFile, ...]
    runs: tuple[RunSpec, ...]
    version: str

    @property
    def name(self) -> str:
        """The set name (results go to DIR/SET/)."""
        return self.set_file.model.set


def swept_order(set_file: SetFile) -> list[str]:
    """Names of swept parameters (sweep and zip) in the order the file lists them."""
    model = set_file.model
    names = [("sweep", n) for n in model.sweep] + [("zip", n) for n in model.zip]
    return [name for _, name in sorted(names, key=lambda k: set_file.where(k)[1:])]


def _combinations(set_file: SetFile) -> Iterator[dict[str, float]]:
    """Every combination of the full sweep x zip, as {parameter: value}."""
    model = set_file.model
    sweep_names, zip_names = list(model.sweep), list(model.zip)
    zip_rows = list(zip(*model.zip.values())) if zip_names else [()]
    for values in itertools.product(*model.sweep.values()):
        for row in zip_rows:
            yield {**dict(zip(sweep_names, values)), **dict(zip(zip_names, row))}


def _strings(value: Any) -> Iterator[str]:
    """Every string inside nested dicts, lists and tuples."""
    if isinstance(value, str):
        yield value
    elif isinstance(value, dict):
        for item in value.values():
            yield from _strings(item)
    elif isinstance(value, (list, tuple)):
        for item in value:
            yield from _strings(item)


def _mechanism_in_use(cf: CaseFile) -> dict:
    """The mechanism as the case uses it: force elements outside its `loads:` list and
    elements of switched-off effects left out (their parameters do not change the run)."""
    mech = cf.mechanism.model_dump()
    effects = dict(cf.case.effects)
    mech["forces"] = {
        name: f
        for name, f in mech.get("forces", {}).items()
        if (cf.case.loads is None or name in cf.case.loads)
        and effects.get(ELEMENT_EFFECTS.get(f.get("type", ""), ""), True)
    }
    if not effects.get("contact", True):
        mech["contacts"], mech["limits"] = {}, {}
    return mech


def used_parameters(cf: CaseFile) -> set[str]:
    """Parameters of a case named in an expression or a numeric field of the case or of
    the part of its mechanism the case uses (`loads:`, `effects:`)."""
    in_use = _mechanism_in_use(cf)
    names: set[str] = set()
    for text in _strings([cf.case.model_dump(), in_use]):
        try:
            names |= parse(text).names()
        except ExpressionError:  # a plain name or text, not an expression
            continue
    names |= {name for path, name in cf.parameter_refs if _in_use(path, in_use)}
    return names & set(cf.parameters)


def _in_use(path: tuple[str, ...], mechanism: dict) -> bool:
    """Whether a field at `path` (case keys, or "mechanism", ...) is in the part of the
    mechanism the case uses: not under a left-out force element or contact."""
    if len(path) < 3 or path[0] != "mechanism" or path[1] not in ("forces", "contacts", "limits"):
        return True
    return path[2] in mechanism.get(path[1], {})


def _case_runs(
    set_file: SetFile,
    cf: CaseFile,
    order: list[str],
    version: str,
    what_if: Pairs,
    written: Labels,
) -> list[RunSpec]:
    """The runs of one case: combinations restricted to the parameters it uses."""
    fixed = {n: v for n, v in set_file.model.parameters.items() if n in cf.parameters}
    overrides = tuple((n, v) for n, v in what_if if n in cf.parameters)
    used = used_parameters(cf)
    named = tuple((n, v) for n, v in overrides if n in used)
    mine = [name for name in order if name in used]
    seen: dict[Pairs, None] = {}
    for combination in _combinations(set_file):
        seen.setdefault(tuple((n, float(combination[n])) for n in mine), None)
    runs = []
    for swept in seen:
        parameters = tuple({**cf.parameters, **fixed, **dict(swept), **dict(overrides)}.items())
        runs.append(
            RunSpec(
                run_name(cf.case.case, swept + named, written),
                cf.case.case,
                str(Path(cf.path).resolve()),
                parameters,
                swept,
                run_hash(cf.input_sha256, parameters, version),
                overrides,
            )
        )
    return runs


def _what_if_problems(
    set_file: SetFile, cases: list[CaseFile], what_if: Sequence[Override]
) -> list[Diagnostic]:
    """`--set` overrides of a set: each must name a parameter of the set or of one of its
    cases, with the dimension of each definition, and not a swept one."""
    sources = [[set_file.locator]]
    sources += [[cf.locators["mechanism"], cf.locators["case"]] for cf in cases]
    found, known = [], set()
    for locators in sources:
        definitions = defined_parameters(locators)
        known |= set(definitions)
        mine = [o for o in what_if if o.name in definitions]
        found += override_problems(mine, definitions, set_file.locator, "the set")
    unknown = [o for o in what_if if o.name not in known]
    found += override_problems(unknown, {}, set_file.locator, "the set or its cases")
    model = set_file.model
    for override in what_if:
        section = "sweep" if override.name in model.sweep else "zip"
        if override.name in model.sweep or override.name in model.zip:
            found.append(
                set_file.locator.diagnostic(
                    (section, override.name),
                    f"{override.option}: the set varies '{override.name}' in its {section}",
                    hint="a --set value would replace every value of the "
                    f"{section}: remove it from the {section} or from --set",
                )
            )
    return found


def compile_set(
    set_file: SetFile,
    cases: list[CaseFile],
    *,
    version: str | None = None,
    what_if: Sequence[Override] = (),
) -> CompiledSet:
    """Runs of a loaded set whose case files are loaded; InputError lists every problem
    (unknown parameter, request or duplicate names, with file:line:col and a hint).
    `what_if` (`--set`) overrides parameters in every run of a case that has them."""
    found = [
        d for d in check_set_cases(set_file.model, set_file.locator, cases) if d.severity == "error"
    ]
    found += [
        d
        for d in check_reference_curves(set_file.model, set_file.locator, set_file.path, cases)
        if d.severity == "error"
    ]
    found += _what_if_problems(set_file, cases, what_if)
    if found:
        raise InputError(found)
    version = version or package_version()
    order = swept_order(set_file)
    given = pairs(what_if)
    written = {**written_values(set_file), **labels(what_if)}
    runs = [
        spec for cf in cases for spec in _case_runs(set_file, cf, order, version, given, written)
    ]
    found = name_clashes(set_file, runs) + _compared_runs(set_file, runs)
    if found:
        raise InputError(found)
    return CompiledSet(set_file, tuple(cases), tuple(runs), version)


def _compared_runs(set_file: SetFile, runs: list[RunSpec]) -> list[Diagnostic]:
    """A comparison's reference and runs must be runs of the set (names as run)."""
    names = {spec.name for spec in runs}
    found = []
    for name, comparison in set_file.model.comparisons.items():
        keys = [("reference",), *(("runs", i) for i in range(len(comparison.runs)))]
        for key, run in zip(keys, [comparison.reference, *comparison.runs]):
            if run not in names:
                found.append(
                    unknown(set_file.locator, ("comparisons", name, *key), "run", run, names)
                )
    return found


def load_and_compile_set(
    path: str | Path, *, version: str | None = None, what_if: Sequence[Override] = ()
) -> CompiledSet:
    """Load a set file and all its cases, then compile (with the `--set` overrides
    `what_if`); InputError with every problem of the set and of its case files at once."""
    set_file = load_set(path)
    cases, found = load_set_cases(set_file)
    if any(d.severity == "error" for d in found):
        raise InputError([d for d in found if d.severity == "error"])
    return compile_set(set_file, cases, version=version, what_if=what_if)


def case_of_run(path: str | Path, run: str) -> CaseFile | list[str]:
    """The case of the run named `run` of the set file `path`, loaded with the run's
    parameter values (InputError on bad input), or the names of the set's runs, in order,
    when it has no run of that name."""
    runs = load_and_compile_set(path).runs
    spec = next((r for r in runs if r.name == run), None)
    if spec is None:
        return [r.name for r in runs]
    return load_case(spec.case_path, overrides=dict(spec.parameters))
