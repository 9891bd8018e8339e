"""Static and quasi-static equilibria (inertia ignored): the balance and its stiffness,
Newton with line search, pseudo-transient continuation and the steppers."""
