"""Load-case sets: compiled into run specifications, run as a campaign on an executor, reported."""
