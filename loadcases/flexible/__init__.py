"""Stiffness and mass of flexible components from files: the readers that turn a neutral
file, Matrix Market or NASTRAN (OP4, DMIG) export into a `mechlib.flexible.FEModel` (SI
units, checked), the writer of the neutral format, and the cache of reductions.

Entry points: `read.read_fe_model(path)` (a JSON header that names the matrices),
`neutral.write_neutral(...)`, `cache.cached(key_parts, compute)`. See
docs/flexible-bodies-import.md for the formats.
"""
