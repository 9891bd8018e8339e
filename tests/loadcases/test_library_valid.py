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
