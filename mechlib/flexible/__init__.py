"""Flexible bodies: finite element models, Craig-Bampton reduction, modal components (SI).

Each name is imported on first use (PEP 562): a mechanism without flexible bodies, whose
`System` imports `mechlib.flexible.attached`, loads no scipy.sparse."""

from __future__ import annotations

from typing import TYPE_CHECKING

from mechlib.core.lazy import lazy_names

if TYPE_CHECKING:
    from mechlib.flexible.fe_model import COMPONENTS, FEModel

__all__ = ["COMPONENTS", "FEModel"]

__getattr__, __dir__ = lazy_names(
    __name__, dict.fromkeys(__all__, "mechlib.flexible.fe_model"), globals(), __all__
)
