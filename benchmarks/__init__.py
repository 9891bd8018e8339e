"""Speed and accuracy benchmarks of `loads` against Exudyn (see README.md)."""
