"""Studies over many solutions of one case: work-precision (`loads accuracy`)."""
