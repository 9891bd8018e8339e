"""The files of one run: its outcome, NAME.csv / NAME.summary.json (/ NAME.xlsx) written atomically, read back."""
