"""Every shipped YAML file of `loadcases/library/` passes `loads validate` (the same checks as
`loads run` short of solving), so a library file never breaks unnoticed when the case
language or a mechanism changes. The files are run by their own tests and `make demo`."""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.sets.precheck import file_problems

LIBRARY = Path(__file__).resolve().parents[2] / "loadcases" / "library"
FOLDERS = sorted({p.parent for p in LIBRARY.rglob("*.yaml")})


@pytest.mark.parametrize("folder", FOLDERS, ids=lambda p: p.relative_to(LIBRARY).as_posix())
def test_every_library_file_validates(folder: Path) -> None:
    files = sorted(folder.glob("*.yaml"))
    assert files
    errors = [d.format() for path in files for d in file_problems(path) if d.severity == "error"]
    assert errors == []


def test_set_validation_loads_each_file_once(monkeypatch, tmp_path) -> None:
    """`loads validate` of the door set loads each of its 22 case files once and parses
    each file (set, cases, mechanism) once; a second validation, as another command would,
    reads every tree from the cache folder (loadcases.yamlfiles.parse_cache) and parses none."""
    import loadcases.inputs.loader as loader
    import loadcases.yamlfiles.source as source

    monkeypatch.setenv("LOADS_CACHE_DIR", str(tmp_path))  # nothing parsed before
    monkeypatch.setattr(source, "_PARSED", source.OrderedDict())
    monkeypatch.setattr(source, "_parsed_size", 0)
    loaded, parsed = [], []
    real_load, real_parse = loader.load_case, source.parse_yaml
    monkeypatch.setattr(loader, "load_case", lambda p, *a, **k: loaded.append(p) or real_load(p))
    monkeypatch.setattr(source, "parse_yaml", lambda t, f: parsed.append(f) or real_parse(t, f))
    door = LIBRARY / "door" / "door.set.yaml"
    assert [d for d in file_problems(door) if d.severity == "error"] == []
    assert len(loaded) == len(set(loaded)) == 22
    assert len(parsed) == len(set(parsed)) == 24
    source._PARSED.clear()
    assert [d for d in file_problems(door) if d.severity == "error"] == []
    assert len(parsed) == 24
