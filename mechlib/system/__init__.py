"""A mechanism compiled to arrays (`System`): its topology (bodies, rows, elements bound to
indices) and its evaluation (constraints, mass, forces), the planar reduction, saddle
factors on its pattern, reaction-dependent loads and the differenced tangent columns."""
