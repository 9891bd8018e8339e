"""NASTRAN bulk data as a stiffness and mass source: DMIG matrices (the punch of
`PARAM,EXTOUT,DMIGPCH` or hand-written K2GG/M2GG input), GRID coordinates, the ASET/ASET1
grids and PARAM,WTMASS. Small field (8-character fields), large field (`DMIG*`, 16-character
fields, `*` continuation lines) and free field (commas) are read; `$` starts a comment.

DMIG entries: a header `DMIG NAME 0 IFO TIN TOUT POLAR - NCOL`, then one entry per column
`DMIG NAME GJ CJ - G1 C1 A1 B1 / G2 C2 A2 B2 ...` (term at row (Gi, Ci), column (GJ, CJ)).
IFO 6 (symmetric) gives one triangle, mirrored here; TIN 1 or 2 (real).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from loadcases.flexible.bounds import file_size_problem, node_id_problem
from loadcases.flexible.values import FileFormatError, nastran_real
from loadcases.foundation.limits import MAX_FE_DOF

__all__ = ["BulkData", "Card", "DmigMatrix", "parse_cards", "read_bulk"]

Dof = tuple[int, int]  # grid id, component 1-6


@dataclass
class Card:
    """One logical bulk-data entry: its name, its data fields (field 2 on) and first line."""

    name: str
    fields: list[str]
    line: int


@dataclass
class DmigMatrix:
    """One DMIG matrix: form (IFO) and its terms by (row DOF, column DOF)."""

    name: str
    form: int
    line: int
    terms: dict[tuple[Dof, Dof], float] = field(default_factory=dict)


@dataclass
class BulkData:
    """What a stiffness/mass import needs from bulk data files."""

    matrices: dict[str, DmigMatrix] = field(default_factory=dict)
    grids: dict[int, tuple[tuple[float, float, float], str, int]] = field(default_factory=dict)
    aset: dict[Dof, tuple[str, int]] = field(default_factory=dict)  # DOF -> (file, line)
    wtmass: tuple[float, str, int] | None = None  # value, file, line


def _fixed_fields(line: str, width: int, count: int) -> list[str]:
    return [line[8 + width * k : 8 + width * (k + 1)].strip() for k in range(count)]


def parse_cards(text: str) -> list[Card]:
    """The logical entries of bulk-data text, continuations joined."""
    cards: list[Card] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("$", 1)[0].rstrip().expandtabs(8)
        if not line.strip():
            continue
        if "," in line:
            parts = [p.strip() for p in line.split(",")]
            # missing trailing fields are blank, as in the fixed formats
            first, fields = parts[0], (parts[1:9] + [""] * 8)[:8]
        else:
            first = line[:8].strip()
            large = first.endswith("*") or first.startswith("*")
            fields = _fixed_fields(line[:72], 16 if large else 8, 4 if large else 8)
        if first == "" or first[0] in "+*":
            if not cards:
                raise FileFormatError("a continuation line without an entry before it", number)
            cards[-1].fields += fields
        else:
            cards.append(Card(first.rstrip("*").upper(), fields, number))
    return cards


def _integer(card: Card, text: str, what: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise FileFormatError(
            f"{card.name}: {what}: expected an integer, got '{text[:20]}'", card.line
        ) from None


def _grid_id(card: Card, text: str, what: str) -> int:
    """A grid id of the entry: an integer 1 to MAX_NODE_ID."""
    value = _integer(card, text, what)
    problem = node_id_problem(value)
    if problem is not None:
        raise FileFormatError(f"{card.name}: {what}: {problem}", card.line)
    return value


def _int(card: Card, index: int, what: str, default: int | None = None) -> int:
    text = card.fields[index] if index < len(card.fields) else ""
    if not text and default is not None:
        return default
    return _integer(card, text, what)


def _components(card: Card, text: str) -> list[int]:
    """`123456` -> [1, ..., 6]; a scalar point (0 or blank) is refused."""
    if not text or not text.isdigit() or "0" in text or any(c > "6" for c in text):
        raise FileFormatError(
            f"{card.name}: component '{text}': expected digits 1-6 (scalar points are not "
            "supported: export the matrices of grids)",
            card.line,
        )
    return [int(c) for c in text]


def _component(card: Card, text: str) -> int:
    """One component 1-6 (a DMIG row or column)."""
    found = _components(card, text)
    if len(found) != 1:
        raise FileFormatError(f"{card.name}: component '{text}': expected one of 1-6", card.line)
    return found[0]


def _dmig(card: Card, bulk: BulkData) -> None:
    name = card.fields[0].upper()
    column = _int(card, 1, "GJ")
    if column != 0:
        column = _grid_id(card, card.fields[1], "GJ")
    if column == 0:  # the header entry
        form, kind = _int(card, 2, "IFO"), _int(card, 3, "TIN")
        if kind not in (1, 2):
            raise FileFormatError(f"DMIG {name}: TIN {kind}: only real matrices (1, 2)", card.line)
        if form not in (1, 2, 6):
            raise FileFormatError(f"DMIG {name}: IFO {form}: expected 1, 2 or 6", card.line)
        if name in bulk.matrices:
            raise FileFormatError(f"DMIG {name} defined twice", card.line)
        bulk.matrices[name] = DmigMatrix(name, form, card.line)
        return
    matrix = bulk.matrices.get(name)
    if matrix is None:
        raise FileFormatError(f"DMIG {name}: a column before its header entry", card.line)
    cj = _component(card, card.fields[2] if len(card.fields) > 2 else "")
    terms = card.fields[4:]
    for k in range(0, len(terms), 4):
        group = terms[k : k + 4] + [""] * 3
        if not group[0]:
            continue
        if not group[2]:
            raise FileFormatError(f"DMIG {name}: row {group[0]}: no value", card.line)
        key = ((_grid_id(card, group[0], "G"), _component(card, group[1])), (column, cj))
        if key in matrix.terms:
            raise FileFormatError(f"DMIG {name}: term {key} given twice", card.line)
        matrix.terms[key] = nastran_real(group[2], card.line)


def _grid(card: Card, bulk: BulkData, file: str) -> None:
    grid = _grid_id(card, card.fields[0] if card.fields else "", "ID")
    cp, cd = _int(card, 1, "CP", 0), _int(card, 5, "CD", 0)
    if cp != 0 or cd != 0:
        raise FileFormatError(
            f"GRID {grid}: coordinate system {cp or cd}: only the basic system (0) is read; "
            "export the grid in basic coordinates",
            card.line,
        )
    # blank (or missing) coordinates are 0.0, as NASTRAN reads them
    cells = (card.fields + [""] * 5)[2:5]
    xyz = tuple(nastran_real(cell or "0", card.line) for cell in cells)
    if grid in bulk.grids:
        raise FileFormatError(f"GRID {grid} given twice", card.line)
    bulk.grids[grid] = ((xyz[0], xyz[1], xyz[2]), file, card.line)


def _aset(card: Card, bulk: BulkData, file: str) -> None:
    where = (file, card.line)
    if card.name == "ASET":
        pairs = [(card.fields[k], card.fields[k + 1]) for k in range(0, len(card.fields) - 1, 2)]
        for grid, text in pairs:
            if grid:
                for c in _components(card, text):
                    bulk.aset[(_grid_id(card, grid, "grid"), c)] = where
        return
    comps = _components(card, card.fields[0])
    grids = [g for g in card.fields[1:] if g]
    ids: list[int] = []
    k = 0
    while k < len(grids):
        if grids[k].upper() == "THRU" and ids and k + 1 < len(grids):
            ids += _thru(card, ids[-1], _grid_id(card, grids[k + 1], "grid"))
            k += 2
            continue
        ids.append(_grid_id(card, grids[k], "grid"))
        k += 1
    for node in ids:
        for c in comps:
            bulk.aset[(node, c)] = where
    if len(bulk.aset) > MAX_FE_DOF:
        raise FileFormatError(
            f"{card.name}: the ASET entries name more than {MAX_FE_DOF:,} DOF (the input limit)",
            card.line,
        )


def _thru(card: Card, first: int, last: int) -> range:
    """The grids after `first` up to `last` of `first THRU last`, at most MAX_FE_DOF // 6."""
    if last <= first:
        raise FileFormatError(
            f"{card.name}: {first} THRU {last}: expected THRU to a larger grid id", card.line
        )
    if last - first > MAX_FE_DOF // 6:
        raise FileFormatError(
            f"{card.name}: {first} THRU {last} names {last - first + 1:,} grids: at most "
            f"{MAX_FE_DOF // 6:,} (the input limit of {MAX_FE_DOF:,} DOF)",
            card.line,
        )
    return range(first + 1, last + 1)


def read_bulk(paths: list[Path]) -> BulkData:
    """DMIG, GRID, ASET/ASET1 and PARAM,WTMASS of the files (other entries are skipped);
    FileFormatError naming the file and line of the first entry that cannot be read."""
    bulk = BulkData()
    for path in dict.fromkeys(paths):
        too_large = file_size_problem(path)
        if too_large is not None:
            raise FileFormatError(too_large, 0, Path(path))
        text = Path(path).read_text(encoding="utf-8", errors="replace")
        try:
            for card in parse_cards(text):
                _entry(card, bulk, str(path))
        except FileFormatError as error:
            raise FileFormatError(error.message, error.line, Path(path)) from None
    return bulk


def _entry(card: Card, bulk: BulkData, file: str) -> None:
    if card.name == "DMIG":
        _dmig(card, bulk)
    elif card.name == "GRID":
        _grid(card, bulk, file)
    elif card.name in ("ASET", "ASET1"):
        _aset(card, bulk, file)
    elif card.name == "PARAM" and card.fields and card.fields[0].upper() == "WTMASS":
        value = nastran_real(card.fields[1] if len(card.fields) > 1 else "", card.line)
        if bulk.wtmass is not None and bulk.wtmass[0] != value:
            raise FileFormatError(
                f"PARAM,WTMASS given twice ({bulk.wtmass[0]:g}, {value:g})", card.line
            )
        bulk.wtmass = (value, file, card.line)
