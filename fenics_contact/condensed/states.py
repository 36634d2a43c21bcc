"""Contact states of the condensed method's vertices and its failure."""
from __future__ import annotations

import numpy as np

__all__ = ["OPEN", "SLIP", "STICK", "P_TOL", "T_TOL", "classify", "StepFailure"]

OPEN, SLIP, STICK = 0, 1, 2
# State of a vertex from its values: open if p <= P_TOL * max p; at the Coulomb bound (slip) if
# |t| >= (1 - T_TOL) mu p; stick otherwise. mu = 0: every loaded vertex slips.
P_TOL, T_TOL = 1e-10, 1e-8


def classify(pressure: np.ndarray, traction: np.ndarray, mu: float) -> np.ndarray:
    """Vertex states (0 open, 1 slip, 2 stick) from the pressure (> 0 compression) and the tangential traction
    (2D: either sign; 3D: its magnitude) with the friction coefficient ``mu``."""
    pressure, traction = np.asarray(pressure, float), np.asarray(traction, float)
    pmax = float(np.max(pressure)) if pressure.size else 0.0
    loaded = pressure > P_TOL * pmax
    at_bound = np.abs(traction) >= (1.0 - T_TOL) * mu * pressure
    return np.where(loaded, np.where(at_bound, SLIP, STICK), OPEN)


class StepFailure(RuntimeError):
    """The condensed semismooth Newton did not converge: ``args`` are the message and the residual history."""
