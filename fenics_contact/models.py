"""The bulk models by name (:data:`MODELS`): the capability grid's ``model`` axis, the demos' ``--model``."""
from __future__ import annotations

from .incompressible import MixedLinearElastic, MixedNeoHookean
from .materials import LinearElastic, NeoHookean

__all__ = ["MODELS"]

MODELS = {"linear": LinearElastic, "neohookean": NeoHookean, "neohookean-mixed": MixedNeoHookean,
          "linear-mixed": MixedLinearElastic}
