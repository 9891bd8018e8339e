"""Reports over saved runs: envelopes, factors and margins, envelope curves, plots, the sizing
workbook."""
