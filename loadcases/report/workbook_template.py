"""The sizing workbook's template: named styles and a cover sheet a company can restyle.

`templates/envelope.xlsx` is made by `templates/make_template.py` from `build_template()`.
The writer (`loadcases.report.workbook`) only relies on:
- the named styles of `STYLES` (restyle them in Excel: Home > Cell Styles > Modify); any
  that a template lacks are added with the defaults below;
- a sheet named `Cover` whose column A holds the labels of `COVER_FIELDS`: the value of
  each goes in column B of the row where its label is found (rows may be moved, other
  cells, logos and sheets of the template are kept as they are).
"""

from __future__ import annotations

from typing import Any

__all__ = ["COVER_FIELDS", "COVER_SHEET", "STYLES", "build_template", "ensure_styles"]

COVER_SHEET = "Cover"
COVER_FIELDS = (
    "Set",
    "Set file",
    "Date (UTC)",
    "Engine version",
    "Runs",
    "Failed runs",
    "Reused runs",
)
TITLE = "Mechanism load envelope"
_BLUE, _GREY, _RED = "1F4E79", "D9E1F2", "F8CBAD"


def _style_specs() -> dict[str, dict[str, Any]]:
    """Named style name -> font, fill, number format and alignment keyword arguments."""
    from openpyxl.styles import Alignment, Font, PatternFill

    solid = lambda colour: PatternFill("solid", start_color=colour, end_color=colour)  # noqa: E731
    return {
        "loads title": {"font": Font(size=16, bold=True, color=_BLUE)},
        "loads label": {"font": Font(bold=True)},
        "loads header": {
            "font": Font(bold=True, color="FFFFFF"),
            "fill": solid(_BLUE),
            "alignment": Alignment(wrap_text=True, vertical="top"),
        },
        "loads number": {"number_format": "0.000E+00"},
        "loads time": {"number_format": "0.000000"},
        "loads margin": {"number_format": "0.00"},
        "loads text": {"alignment": Alignment(vertical="top")},
        "loads failed": {"fill": solid(_RED)},
        "loads note": {"font": Font(italic=True, color="595959"), "fill": solid(_GREY)},
    }


STYLES = (
    "loads title",
    "loads label",
    "loads header",
    "loads number",
    "loads time",
    "loads margin",
    "loads text",
    "loads failed",
    "loads note",
)


def ensure_styles(workbook: Any) -> None:
    """Register the named styles of `STYLES` that `workbook` does not have yet."""
    from openpyxl.styles import NamedStyle

    present = set(workbook.named_styles)
    for name, spec in _style_specs().items():
        if name not in present:
            workbook.add_named_style(NamedStyle(name=name, **spec))


def build_template() -> Any:
    """A new openpyxl Workbook with the named styles and the cover sheet."""
    from openpyxl import Workbook

    workbook = Workbook()
    ensure_styles(workbook)
    cover = workbook.active
    cover.title = COVER_SHEET
    cover["A1"] = TITLE
    cover["A1"].style = "loads title"
    for row, label in enumerate(COVER_FIELDS, start=3):
        cover.cell(row=row, column=1, value=label).style = "loads label"
    note = cover.cell(
        row=len(COVER_FIELDS) + 4,
        column=1,
        value=(
            "Sheets: Cases (every run), Envelope (max/min per result column, ultimate loads, "
            "margins), Curves (envelopes over the abscissa, charts), one sheet of time histories "
            "per run, Provenance (inputs, hashes, settings)."
        ),
    )
    note.style = "loads note"
    cover.column_dimensions["A"].width = 22
    cover.column_dimensions["B"].width = 60
    return workbook
