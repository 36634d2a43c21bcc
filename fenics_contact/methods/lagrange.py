"""Lagrange multipliers: the contact pressure an unknown, exact nodal Signorini conditions."""
from ..laws import LagrangeMultiplier
from .spec import Method, Parameter, Sweep, rule

__all__ = ["METHOD", "mixed_models", "multiplier_rules"]


def mixed_models() -> tuple:
    """The bulk models whose unknown is (displacement, pressure)."""
    from ..models import MODELS

    return tuple(name for name, cls in MODELS.items() if cls.mixed)


def multiplier_rules(method: str) -> tuple:
    """The capability rules of a method whose pressure is an unknown (the multipliers' element)."""
    return (rule("quadrature 'nodal' (P1) or 'simpson' (P2)", "the multipliers' constraint sits at the vertices",
                 method=method, quadrature=("gauss", "segment")),
            rule("degree 1", "the multipliers' quadratic (two-point) element is 2D", method=method, degree=2, dim=3),
            rule("quadrature 'simpson' (the two-point element)", "the vertex rule alone leaves the mid-side nodes of "
                 "quadratic facets without the pressure's work", method=method, degree=2, quadrature="nodal"),
            rule("model 'linear' or 'neohookean' (or another method)", "its unknown already holds the contact "
                 "pressure as its second field, where a mixed model has its own", method=method,
                 model=mixed_models()),
            rule("passes 'one'", "two passes of exact constraints over-constrain the surface (surface locking, "
                 "a pressure split arbitrarily between the passes)", method=method, passes="two"),
            *((rule("sliding 'finite' (or method coulomb or lagrange)", "the regularised multipliers enforce the gap "
                    "of the current facets", method=method, sliding="small"),) if method != "lagrange" else ()))


# Exact friction with the traction an unknown (Alart-Curnier, fenics_contact.multiplier_friction): what it takes.
FRICTION_RULES = (

    rule("degree 1 or mu 0", "the multipliers' tangential law sits at the vertices of flat facets", method="lagrange",
         friction=True, degree=2),
    # Measured: mindlin3d (c 1e5, rtol 1e-2) "converged" with the cap slid 0.48 R off its contact, no force
    rule("solver 'direct' or 'iterative' (or mu 0)", "its semismooth Newton takes exact linear solves (a loose one "
         "can slide a body held by friction alone off its support)", method="lagrange", friction=True,
         solver="inexact"),
)

METHOD = Method(
    name="lagrange", summary="exact nodal Signorini conditions (with friction: Alart-Curnier's Coulomb or Tresca "
                             "law), the pressure (traction) an unknown, one semismooth Newton on the sparse system",
    law=LagrangeMultiplier,
    parameters=(Parameter("c", "K", "complementarity parameter c (pressure per length; steers Newton only; with "
                                    "friction and no --K: a tenth of E / h, from the problem)"),),
    rigid="fenics_contact.methods.builders:multiplier_surface",
    two_body="fenics_contact.methods.builders:multiplier_two_body",
    friction="law", sweep=Sweep("narrow", "K"), rules=multiplier_rules("lagrange") + FRICTION_RULES)
