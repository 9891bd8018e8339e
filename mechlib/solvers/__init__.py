"""The analyses and their one loop: the stepper contract, `march` with events, assembly
and consistent states, kinematic, static and quasi-static, generalized-alpha, Radau, modes
and `solve`, the one entry point."""
