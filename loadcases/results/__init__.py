"""The files of one run: its outcome, NAME.csv / NAME.summary.json (/ NAME.xlsx) written and
read back."""
