"""Write templates/envelope.xlsx, the sizing workbook template (styles and cover sheet).

Run from the repository root: `.venv/bin/python templates/make_template.py`. A company may
then restyle the file in Excel (cell styles named `loads ...`, the Cover sheet) and point a
set's `report: {template: ...}` at its copy; see loadcases/report/workbook_template.py.
"""

from pathlib import Path

from loadcases.foundation.atomic import atomic_path
from loadcases.report.workbook_template import build_template

TARGET = Path(__file__).resolve().parent / "envelope.xlsx"


def main() -> None:
    """Build the template and save it atomically next to this script."""
    workbook = build_template()
    with atomic_path(TARGET) as tmp:
        workbook.save(tmp)
    print(f"wrote {TARGET}")


if __name__ == "__main__":
    main()
