"""Pictures and animations of a mechanism along a run."""
