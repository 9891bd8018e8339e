"""The input files: which kind a file is, reading them into validated models (parameters put
in place first), case skeletons."""
