"""Cross-constraints (Zavarise, Wriggers & Schrefler 1998)."""
from ..laws import CrossConstraints
from .spec import Method, Parameter, Sweep, rule

__all__ = ["METHOD"]

METHOD = Method(
    name="cross", summary="cross-constraints: exponential on the open side, F^ + K^ g closed; F^ augmented",
    law=CrossConstraints,
    parameters=(Parameter("K_hat", "K", "stiffness K_hat at g = 0 (pressure per length)"),
                Parameter("F_hat", "F_hat", "target pressure at g = 0", "nonnegative", 0.0),
                Parameter("a", "a", "shape parameter in [0, 1) (> 0.1: adhesion)", "unit", 0.0),
                Parameter("tau", "tau", "K_hat <- tau K_hat per augmentation (>= 1)", "exponent", 1.0)),
    augment=10, friction="law", sweep=Sweep("narrow", "K", augmented=True, colour="tab:orange", size=8.0),
    rules=(rule("method penalty, auglag or compliance", "the segment element's NumPy law fails on cross-constraints' "
                "open branch (a singular first tangent: MUMPS fails at the first iterate; found by the full grid)",
                kind="two-body", quadrature="segment", method="cross"),))
