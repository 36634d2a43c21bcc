"""The multipliers' penalty regularisation ``p = eps <g>`` (Papadopoulos & Solberg), the pressure an unknown."""
from ..laws import PenaltyMultiplier
from .lagrange import multiplier_rules
from .spec import Method, Parameter, Sweep

__all__ = ["METHOD"]

METHOD = Method(
    name="penalty_multiplier", summary="the multipliers' penalty regularisation p = eps <g>, p an unknown",
    law=PenaltyMultiplier,
    parameters=(Parameter("K", "K", "penalty eps (pressure per length)"),),
    rigid="fenics_contact.methods.builders:multiplier_surface",
    two_body="fenics_contact.methods.builders:multiplier_two_body",
    sweep=Sweep("narrow", "K"), rules=multiplier_rules("penalty_multiplier"))
