"""The files of one run: its outcome, NAME.csv / NAME.summary.json (/ NAME.xlsx) read back."""
