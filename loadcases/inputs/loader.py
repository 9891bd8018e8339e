"""Input files -> validated models in SI floats, with every problem reported at once.

`load_case`, `load_mechanism` and `load_set` raise InputError carrying all diagnostics
(errors and warnings); on success the warnings are kept on the returned object.
"""

from __future__ import annotations

import dataclasses
import glob
import hashlib
import json
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ValidationError

from loadcases.checks import (
    check_case,
    check_case_alone,
    check_mechanism,
    check_set,
    check_set_cases,
    resolve_initial,
)
from loadcases.checks.dimensions import expression_scope
from loadcases.checks.requests import expression_units
from loadcases.foundation.diagnostics import Diagnostic, InputError
from loadcases.foundation.limits import local_path_problem, pattern_problem
from loadcases.foundation.units import UnitError, dimension_mismatch
from loadcases.inputs.extends import resolve_extends
from loadcases.inputs.hardpoints import expand_hardpoints
from loadcases.inputs.kinds import file_kind, unknown_kind
from loadcases.inputs.overrides import Override, defined_parameters, override_problems, pairs
from loadcases.inputs.parameter_refs import (
    ParameterRef,
    Unresolved,
    parameter_values,
    put_parameters,
)
from loadcases.inputs.partial import beside_removed, validated_in_part
from loadcases.inputs.reference_tables import check_reference_curves
from loadcases.schema import CaseModel, FileUnits, MechanismModel, SetModel
from loadcases.schema.case import TARGET_FORM
from loadcases.schema.errors import (
    did_you_mean,
    plain_boolean_diagnostics,
    validation_diagnostics,
)
from loadcases.yamlfiles.source import KeyPath, Locator, SourceTree, load_yaml

__all__ = [
    "CaseFile",
    "MechanismFile",
    "SetFile",
    "load_case",
    "load_mechanism",
    "load_set",
    "load_set_cases",
    "parse_key_path",
    "validate_files",
    "validate_set",
]

_KEY_PART = re.compile(r"([^.\[\]]+)|\[(\d+)\]")


def parse_key_path(key: str | KeyPath) -> KeyPath:
    """`"joints.hinge.bodies[1]"` -> `("joints", "hinge", "bodies", 1)` (tuples pass through)."""
    if not isinstance(key, str):
        return tuple(key)
    return tuple(int(index) if index else name for name, index in _KEY_PART.findall(key))


@dataclass(frozen=True)
class MechanismFile:
    """A validated mechanism file."""

    path: str
    model: MechanismModel
    input_sha256: str
    locator: Locator
    warnings: tuple[Diagnostic, ...] = ()

    def where(self, key_path: str | KeyPath) -> tuple[str, int, int]:
        """(file, line, col) of a key such as `"joints.hinge"`."""
        return self.locator.where(parse_key_path(key_path))


@dataclass(frozen=True)
class CaseFile:
    """A validated case with its mechanism (inline or from `mechanism_path`).

    `parameters` are the mechanism's parameters overridden by the case's (SI floats);
    `input_sha256` hashes the case file bytes then the mechanism file bytes. It is the hash
    of what the case was built from: a tree read from the parse cache is used only when its
    entry records this text's SHA-256 and its payload its own digest
    (loadcases.yamlfiles.parse_cache), so no cached tree that differs from the file is
    ever run under the file's hash.
    """

    path: str
    case: CaseModel
    mechanism: MechanismModel
    mechanism_path: str | None
    parameters: dict[str, float]
    input_sha256: str
    locators: dict[str, Locator] = field(repr=False)
    warnings: tuple[Diagnostic, ...] = ()
    # parameters named in numeric fields: (key path, name); mechanism paths start with
    # "mechanism" whether the mechanism is inline or in its own file
    parameter_refs: frozenset[ParameterRef] = frozenset()
    what_if: tuple[Override, ...] = ()  # `--set` overrides, in the order given
    # each parameter's base dimensionality ({"[length]": 1}); None when written without a unit
    parameter_dims: Mapping[str, Mapping[str, float] | None] = field(default_factory=dict)
    # the SI unit of each expression request's column ("" when not known)
    expression_units: Mapping[str, str] = field(default_factory=dict)

    def where(self, kind: str, key_path: str | KeyPath) -> tuple[str, int, int]:
        """(file, line, col) of a key of the `"case"` or the `"mechanism"` (for messages)."""
        return self.locators[kind].where(parse_key_path(key_path))


@dataclass(frozen=True)
class SetFile:
    """A validated set; `case_paths` are its case files, globs expanded, in order."""

    path: str
    model: SetModel
    case_paths: tuple[str, ...]
    locator: Locator
    warnings: tuple[Diagnostic, ...] = ()

    def where(self, key_path: str | KeyPath) -> tuple[str, int, int]:
        """(file, line, col) of a key such as `"sweep.clearance"`."""
        return self.locator.where(parse_key_path(key_path))


def _mapping_check(tree: SourceTree) -> list[Diagnostic]:
    if isinstance(tree.data, dict):
        return []
    return [Diagnostic(tree.file, 1, 1, "", "expected a mapping of keys at the top of the file")]


def _file_units(
    locator: Locator, inherited: dict[str, str]
) -> tuple[dict[str, str], list[Diagnostic]]:
    """Units of bare numbers: the `units:` header over `inherited` (SI where unset)."""
    raw = locator.data.get("units", {}) if isinstance(locator.data, dict) else {}
    try:
        header = FileUnits.model_validate(raw if raw is not None else {})
    except ValidationError as error:
        wrapper = Locator(locator.tree, (*locator.prefix, "units"))
        return dict(inherited), validation_diagnostics(error, FileUnits, wrapper)
    return {**inherited, **header.as_dict()}, []


def _validate(
    model: type[BaseModel], locator: Locator, units: dict[str, str]
) -> tuple[Any, list[Diagnostic]]:
    """The validated model (None if invalid) and the diagnostics of validating it."""
    try:
        valid = model.model_validate(locator.data, context={"units": units})
        return valid, plain_boolean_diagnostics(valid, locator)
    except ValidationError as error:
        return None, _schema_diagnostics(error, model, locator)


def _schema_diagnostics(
    error: ValidationError, model: type[BaseModel], locator: Locator
) -> list[Diagnostic]:
    found = validation_diagnostics(error, model, locator)
    # A bad `units:` header is reported once by _file_units.
    units_key = ".".join(str(p) for p in (*locator.prefix, "units"))
    return [d for d in found if not d.key.startswith(units_key)]


def _validate_partly(
    model: type[BaseModel], locator: Locator, units: dict[str, str]
) -> tuple[Any, list[Diagnostic], Any, frozenset[str]]:
    """`_validate`, and when the file is invalid, its model without the invalid items and
    their names (loadcases.inputs.partial), for the checks of `validate`."""
    try:
        valid = model.model_validate(locator.data, context={"units": units})
        return valid, plain_boolean_diagnostics(valid, locator), None, frozenset()
    except ValidationError as error:
        in_part, removed = validated_in_part(model, locator.data, units, error)
        return None, _schema_diagnostics(error, model, locator), in_part, removed


def _checked(
    case: Any,
    mechanism: Any,
    locators: tuple[Locator, Locator | None],
    case_units: dict[str, str],
    scope: Any,
) -> tuple[Any, list[Diagnostic]]:
    """The case with its initial values resolved, and the semantic problems of a case and
    its mechanism (each None when it could not be validated even in part)."""
    case_locator, mech_locator = locators
    found: list[Diagnostic] = []
    if mechanism is not None and mech_locator is not None:
        motions, parameters = _raw_keys(case_locator.data, "motions", "parameters")
        found += check_mechanism(mechanism, mech_locator, motions, parameters, scope)
    if case is not None and mechanism is not None:
        case, more = resolve_initial(case, mechanism, case_locator, case_units)
        found += more + check_case(case, mechanism, case_locator, scope)
    elif case is not None:
        found += check_case_alone(case, case_locator)
    return case, found


def _sha256(*contents: bytes) -> str:
    digest = hashlib.sha256()
    for content in contents:
        digest.update(content)
    return digest.hexdigest()


def _raise_on_errors(diagnostics: list[Diagnostic]) -> None:
    if any(d.severity == "error" for d in diagnostics):
        raise InputError(diagnostics)


def _read_tree(path: str | Path) -> tuple[SourceTree, list[Diagnostic]]:
    """Parsed tree of `path` with its reading diagnostics; raises InputError if unreadable."""
    tree = load_yaml(path)
    diagnostics = [*tree.diagnostics, *_mapping_check(tree)]
    if not isinstance(tree.data, dict):
        raise InputError(diagnostics)
    return tree, diagnostics


def _read_model(path: str | Path, model_class):
    """(model or None, locator, file units, diagnostics) of one file of a kind."""
    tree, diagnostics = _read_tree(path)
    locator = Locator(tree)
    units, found = _file_units(locator, {})
    model, more = _validate(model_class, locator, units)
    return model, locator, units, diagnostics + found + more


def _prepared_base(tree: SourceTree) -> tuple[list[bytes], list[Diagnostic]]:
    """A base mechanism readied for `extends:`: its hardpoint table read in its own units
    and folder (bytes read, problems)."""
    locator = Locator(tree)
    units, found = _file_units(locator, {})
    tables, more = expand_hardpoints(locator, units)
    return tables, found + more


def _read_mechanism_tree(path: str | Path) -> tuple[SourceTree, list[bytes], list[Diagnostic]]:
    """A mechanism file's tree with the bases it `extends:` merged in, the bytes of those
    bases (for the input hash) and the problems of reading them all."""
    tree, diagnostics = _read_tree(path)
    extended = resolve_extends(tree, _prepared_base)
    return extended.tree, extended.contents, diagnostics + extended.diagnostics


def imported_model_bytes(mechanism: MechanismModel, folder: Path) -> list[bytes]:
    """The contents of the files of every imported flexible body (`flexible: file:`), so
    that a changed matrix is a changed input; files that cannot be read add nothing (the
    build reports them)."""
    out: list[bytes] = []
    for body in mechanism.bodies.values():
        source = getattr(getattr(body, "flexible", None), "file", None)
        if source is None or local_path_problem(source.path, folder, "the mechanism") is not None:
            continue
        # imported here: a mechanism without imported bodies loads no scipy.sparse
        from loadcases.flexible.read import read_fe_model

        try:
            out += [f.read_bytes() for f in read_fe_model(folder / source.path).files]
        except (InputError, OSError):
            continue
    return out


def load_mechanism(path: str | Path) -> MechanismFile:
    """Validated mechanism file; raises InputError with every problem found. Its own
    parameters named in numeric fields are put in place first (as a case does); `extends:`
    merges its base in first (loadcases.inputs.extends)."""
    tree, bases, diagnostics = _read_mechanism_tree(path)
    locator = Locator(tree)
    units, found = _file_units(locator, {})
    tables, more = expand_hardpoints(locator, units)
    found += more
    unresolved: dict[tuple, Unresolved] = {}
    values = {}
    if isinstance(locator.data, dict):
        values = parameter_values(locator.data.get("parameters"), file_units=units)
        put_parameters(locator.data, values, unresolved=unresolved)
    model, more, in_part, removed = _validate_partly(MechanismModel, locator, units)
    diagnostics += found + _name_unknown_parameters(
        more, {"mechanism": unresolved}, {"mechanism": locator}
    )
    if model is not None or in_part is not None:
        scope = expression_scope({n: v.dims for n, v in values.items()}, model_tables(locator))
        checks = check_mechanism(model or in_part, locator, scope=scope)
        diagnostics += beside_removed(checks, removed)
    _raise_on_errors(diagnostics)
    digest = _sha256(Path(path).read_bytes(), *bases, *tables)
    return MechanismFile(str(path), model, digest, locator, tuple(diagnostics))


def _redefined_parameters(case: Locator, mechanism: Locator | None) -> list[Diagnostic]:
    """A case parameter written with a unit of another dimension than the mechanism's
    definition (the rule of `--set`), at the case's key."""
    definitions = defined_parameters([mechanism])
    raw = case.data.get("parameters") if isinstance(case.data, dict) else None
    found = []
    for name, value in raw.items() if isinstance(raw, dict) else ():
        if name not in definitions or not isinstance(value, str):
            continue
        try:
            problem = dimension_mismatch(value, definitions[name][1])
        except UnitError:
            continue  # an unreadable value is reported by the schema
        if problem is not None:
            found.append(
                case.diagnostic(
                    ("parameters", name),
                    f"the mechanism's parameter of another dimension: {problem}",
                )
            )
    return found


def _motion_joint_types(case: Locator, mechanism: Locator | None) -> dict[str, str]:
    """The type of the joint each motion of the raw case drives (as written)."""
    motions = case.data.get("motions") if isinstance(case.data, dict) else None
    raw = mechanism.data if mechanism is not None and isinstance(mechanism.data, dict) else {}
    joints = raw.get("joints")
    joints = joints if isinstance(joints, dict) else {}
    found = {}
    for name, motion in motions.items() if isinstance(motions, dict) else ():
        joint = joints.get(motion.get("joint")) if isinstance(motion, dict) else None
        if isinstance(joint, dict) and isinstance(joint.get("type"), str):
            found[str(name)] = joint["type"]
    return found


def model_tables(locator: Locator) -> Any:
    """The raw `tables:` of a file (as written: their units tell their dimensions)."""
    return locator.data.get("tables") if isinstance(locator.data, dict) else None


def _mechanism_source(
    case_locator: Locator, case_units: dict[str, str], bases: list[bytes]
) -> tuple[Locator | None, str | None, dict[str, str], list[Diagnostic]]:
    """Locator of the case's mechanism (inline or file), its path and inherited units;
    the bytes of the files a mechanism file extends are added to `bases`."""
    raw = case_locator.data.get("mechanism")
    if isinstance(raw, dict):
        inline = Locator(case_locator.tree, ("mechanism",))
        return inline, None, case_units, _inline_extends(inline)
    if not isinstance(raw, str) or not raw.strip():
        return None, None, {}, []
    path = os.path.normpath(os.path.join(os.path.dirname(case_locator.tree.file), raw.strip()))
    if not Path(path).is_file():
        folder = Path(path).parent
        names = [p.name for p in folder.glob("*.y*ml")] if folder.is_dir() else []
        return (
            None,
            path,
            {},
            [
                case_locator.diagnostic(
                    ("mechanism",),
                    f"mechanism file not found: {path}",
                    hint=did_you_mean(Path(path).name, names),
                )
            ],
        )
    try:
        tree, contents, diagnostics = _read_mechanism_tree(path)
    except InputError as error:
        return None, path, {}, list(error.diagnostics)
    bases += contents
    return Locator(tree), path, {}, diagnostics


def _inline_extends(inline: Locator) -> list[Diagnostic]:
    """`extends:`/`remove:` belong to a mechanism file: an error in an inline mechanism."""
    return [
        inline.diagnostic(
            (key,), f"{key}: only in a mechanism file (write the mechanism to its own file)"
        )
        for key in ("extends", "remove")
        if key in inline.data
    ]


def _raw_keys(data: dict[str, Any], *sections: str) -> list[list[str]]:
    """Names defined in `sections` of raw data (known even if the model is invalid)."""
    return [list(data[s]) if isinstance(data.get(s), dict) else [] for s in sections]


def load_case(
    path: str | Path,
    overrides: Mapping[str, float] | None = None,
    *,
    what_if: Sequence[Override] = (),
) -> CaseFile:
    """Validated case with its mechanism merged; raises InputError with every problem found.

    `overrides` (SI) replace parameter values (a set's sweep); `what_if` (`--set`) too, after
    checking that each names a parameter of the case or its mechanism, of the same
    dimension. Parameters named in numeric fields are put in place before validation
    (loadcases.inputs.parameter_refs).
    """
    tree, diagnostics = _read_tree(path)
    case_locator = Locator(tree)
    case_units, found = _file_units(case_locator, {})
    bases: list[bytes] = []  # files the mechanism file extends
    mech_locator, mech_path, inherited, more = _mechanism_source(case_locator, case_units, bases)
    diagnostics += found + more
    if what_if:
        definitions = defined_parameters([mech_locator, case_locator])
        diagnostics += override_problems(what_if, definitions, case_locator, "the case")
        overrides = {**(overrides or {}), **dict(pairs(what_if))}
    mech_units: dict[str, str] = {}
    tables: list[bytes] = []
    if mech_locator is not None:
        mech_units, found = _file_units(mech_locator, inherited)
        tables, more = expand_hardpoints(mech_locator, mech_units)
        diagnostics += found + more
    diagnostics += _redefined_parameters(case_locator, mech_locator)
    unresolved: dict[str, dict] = {"case": {}, "mechanism": {}}
    dimensions: dict[str, Any] = {}
    refs = _put_parameters(
        case_locator, mech_locator, case_units, mech_units, overrides, unresolved, dimensions
    )
    scope = expression_scope(
        dimensions,
        model_tables(mech_locator) if mech_locator is not None else None,
        _motion_joint_types(case_locator, mech_locator),
    )
    case, found, case_in_part, removed = _validate_partly(CaseModel, case_locator, case_units)
    mechanism, mechanism_in_part = None, None
    if mech_locator is not None:
        mechanism, more, mechanism_in_part, gone = _validate_partly(
            MechanismModel, mech_locator, mech_units
        )
        found += more
        removed |= gone
    diagnostics += _name_unknown_parameters(
        found, unresolved, {"case": case_locator, "mechanism": mech_locator}
    )
    # the checks run on the valid part of each file too: every problem in one pass
    checked, found = _checked(
        case or case_in_part,
        mechanism or mechanism_in_part,
        (case_locator, mech_locator),
        case_units,
        scope,
    )
    diagnostics += beside_removed(found, removed)
    case = checked if case is not None else None
    _raise_on_errors(diagnostics)
    if case is None or mechanism is None or mech_locator is None:
        raise InputError(diagnostics)  # not reached: each of them missing is an error above
    contents = [Path(path).read_bytes()] + ([Path(mech_path).read_bytes()] if mech_path else [])
    contents += bases + tables  # bases and hardpoint tables: a changed one is a changed input
    contents += imported_model_bytes(mechanism, Path(mech_path or path).parent)
    if what_if:  # part of the run's identity: never mistaken for the run without them
        contents.append(json.dumps(pairs(what_if)).encode("utf-8"))
    return CaseFile(
        path=str(path),
        case=case,
        mechanism=mechanism,
        mechanism_path=mech_path,
        parameters={**mechanism.parameters, **case.parameters, **(overrides or {})},
        input_sha256=_sha256(*contents),
        locators={"case": case_locator, "mechanism": mech_locator},
        warnings=tuple(diagnostics),
        parameter_refs=frozenset(refs),
        what_if=tuple(what_if),
        parameter_dims=dict(dimensions),
        expression_units=expression_units(case, scope),
    )


def _put_parameters(
    case_locator: Locator,
    mech_locator: Locator | None,
    case_units: dict,
    mech_units: dict,
    overrides,
    unresolved: Mapping[str, dict],
    dimensions: dict[str, Any],
) -> set[ParameterRef]:
    """Parameter values (mechanism, then case, then overrides) put where a numeric field
        names a parameter, in both raw trees; returns the fields so set (key path, name). Texts
        naming unknown parameters go to `unresolved["case"]` and `unresolved["mechanism"]`, each
    parameter's dimension (None: written without a unit) to `dimensions`."""
    mech_data = mech_locator.data if mech_locator is not None else {}
    values = parameter_values(
        mech_data.get("parameters") if isinstance(mech_data, dict) else None, file_units=mech_units
    )
    values = parameter_values(
        case_locator.data.get("parameters"),
        file_units=case_units,
        overrides=overrides,
        earlier=values,
    )
    dimensions.update({name: value.dims for name, value in values.items()})
    used = put_parameters(case_locator.data, values, unresolved=unresolved["case"])
    if mech_locator is not None and mech_locator.data is not case_locator.data.get("mechanism"):
        used |= put_parameters(
            mech_locator.data, values, ("mechanism",), unresolved=unresolved["mechanism"]
        )
    return used


def _name_unknown_parameters(
    diagnostics: list[Diagnostic], unresolved: Mapping[str, Mapping[tuple, Unresolved]], locators
) -> list[Diagnostic]:
    """Each field error about a text that could not be read and that names no known
    parameter, said so: `unknown parameter 'mu_trunion'` with a `did you mean` hint."""
    by_key: dict[tuple[str, str], Unresolved] = {}
    for kind, found in unresolved.items():
        locator = locators.get(kind)
        if locator is None:
            continue
        for path, why in found.items():
            key = ".".join(str(p) for p in locator.prefix)
            for part in path:
                key += f"[{part}]" if isinstance(part, int) else ("." if key else "") + part
            by_key[(locator.tree.file, key)] = why
    out = []
    for d in diagnostics:
        reason = by_key.get((d.file, d.key))
        unreadable = "cannot read" in d.message or d.message.startswith(TARGET_FORM)
        if reason is not None and d.severity == "error" and unreadable:
            d = dataclasses.replace(d, message=reason.message, hint=reason.hint)
        out.append(d)
    return out


def _expand_cases(model: SetModel, locator: Locator) -> tuple[list[str], list[Diagnostic]]:
    """Case files of the set's `cases` patterns (relative to the set file), in order."""
    folder = os.path.dirname(locator.tree.file)
    paths: list[str] = []
    diagnostics: list[Diagnostic] = []
    for index, pattern in enumerate(model.cases):
        if pattern_problem(pattern) is not None:
            continue  # never globbed: check_set reports it
        matches = sorted(glob.glob(os.path.join(folder, pattern), recursive=True))
        if not matches:
            diagnostics.append(
                locator.diagnostic(("cases", index), f"no case file matches '{pattern}'")
            )
        paths += [os.path.normpath(m) for m in matches if os.path.normpath(m) not in paths]
    return paths, diagnostics


def load_set(path: str | Path) -> SetFile:
    """Validated set file with its case patterns expanded; raises InputError on problems."""
    model, locator, _units, diagnostics = _read_model(path, SetModel)
    case_paths: list[str] = []
    if model is not None:
        case_paths, found = _expand_cases(model, locator)
        diagnostics += found + check_set(model, locator)
    _raise_on_errors(diagnostics)
    return SetFile(str(path), model, tuple(case_paths), locator, tuple(diagnostics))


def _validate_one(path: str, done: set[str]) -> list[Diagnostic]:
    """Diagnostics of one file of any kind; a set's cases are validated too (once each)."""
    kind = file_kind(path)
    if kind is None:
        return [unknown_kind(path)]
    if kind == "mechanism":
        return list(load_mechanism(path).warnings)
    if kind == "case":
        return list(load_case(path).warnings)
    return validate_set(path, done)[2]


def validate_set(
    path: str | Path, done: set[str] | None = None
) -> tuple[SetFile, list[CaseFile], list[Diagnostic]]:
    """A set file (InputError if it cannot be loaded), its case files that load (those in
    `done` skipped, `load_set_cases`) and every diagnostic of the set and of its cases."""
    set_file = load_set(path)
    cases, found = load_set_cases(set_file, done)
    checks = check_set_cases(set_file.model, set_file.locator, cases)
    checks += check_reference_curves(set_file.model, set_file.locator, set_file.path, cases)
    return set_file, cases, [*set_file.warnings, *found, *checks]


def load_set_cases(
    set_file: SetFile, done: set[str] | None = None
) -> tuple[list[CaseFile], list[Diagnostic]]:
    """The set's case files that load, and the diagnostics of all of them (warnings, and
    the errors of those that do not load), each file's once: paths in `done` were reported
    already (their cases are still returned, for the set's own checks), the others are
    added to it."""
    done = set() if done is None else done
    cases: list[CaseFile] = []
    found: list[Diagnostic] = []
    for case_path in set_file.case_paths:
        reported = case_path in done
        done.add(case_path)
        try:
            cases.append(load_case(case_path))
        except InputError as error:
            found += [] if reported else error.diagnostics
            continue
        found += [] if reported else cases[-1].warnings
    return cases, found


def validate_files(paths: list[str | Path]) -> list[Diagnostic]:
    """Every diagnostic (errors and warnings) of the given files of any kind, no duplicates."""
    found: list[Diagnostic] = []
    done: set[str] = set()
    for path in paths:
        name = str(path)
        if os.path.normpath(name) in done:
            continue
        done.add(os.path.normpath(name))
        try:
            found += _validate_one(name, done)
        except InputError as error:
            found += error.diagnostics
    return list(dict.fromkeys(found))
