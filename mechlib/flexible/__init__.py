"""Flexible bodies: finite element models, Craig-Bampton reduction, modal components (SI)."""

from mechlib.flexible.fe_model import COMPONENTS, FEModel

__all__ = ["COMPONENTS", "FEModel"]
