"""Generalized-alpha (Arnold & Bruls 2007) for the index-3 equations of motion: its rules
(step size, Newton rate, refactorisation), the Python Newton loop, the compiled kernels, the
compiled whole run and the stepper that joins them to `march`."""
