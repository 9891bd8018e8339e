"""Report templates (`envelope.xlsx`) and case skeletons (`cases/`), installed with loads
so that `loads new` and the workbook writer find them after a plain install."""
