"""What a mechanism is, as the user builds it: bodies, points, joints, motions, tables,
curves, planes and the analysis settings (SI units; no numerics beyond interpolation)."""
