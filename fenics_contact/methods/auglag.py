"""Augmented Lagrangian (Uzawa): ``F = <lam + K g>``, ``lam <- F(g)``."""
from ..laws import AugmentedLagrangian
from .spec import Method, Parameter, Sweep

__all__ = ["METHOD"]

METHOD = Method(
    name="auglag", summary="augmented Lagrangian (Uzawa), F = <lam + K g>", law=AugmentedLagrangian,
    parameters=(Parameter("K", "K", "penalty K (pressure per length)"),
                Parameter("lam0", "lam0", "initial multiplier lam (pressure)", "nonnegative", 0.0)),
    augment=10, friction="law", self_contact="fenics_contact.methods.builders:law_self",
    sweep=Sweep("narrow", "K", augmented=True, colour="tab:green", size=5.0))
