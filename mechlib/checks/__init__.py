"""Checks of a model before and while solving: redundant equations and degrees of freedom
by joint, and near-singular positions (toggles, dead points)."""
