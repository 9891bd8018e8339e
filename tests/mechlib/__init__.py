"""Unit and verification tests of mechlib (closed-form references, stated tolerances)."""
