"""Exact Signorini-Coulomb on the stiffness condensed onto the contact dofs (Renaud & Feng 2003)."""
from ..laws import ExactCoulomb
from .spec import Method, Parameter, Sweep, rule

__all__ = ["METHOD"]

METHOD = Method(
    name="coulomb", summary="exact Signorini-Coulomb on the condensed stiffness", law=ExactCoulomb,
    parameters=(Parameter("mu", "mu", "Coulomb friction coefficient (0: frictionless)", "nonnegative", 0.0),),
    rigid="fenics_contact.methods.builders:condensed_surface",
    two_body="fenics_contact.methods.builders:condensed_two_body",
    friction="own", sweep=Sweep("once", None, colour="tab:brown", size=8.0, reference=True),
    rules=(rule("an axis-aligned half-plane (or another method)",
                "coulomb condenses the displacement component along an axis-aligned normal",
                method="coulomb", obstacle=("plane", "curved")),
           rule("passes 'one'", "coulomb pairs each slave vertex once with the master surface (two passes would "
                "constrain each pair twice)", kind="two-body", method="coulomb", passes="two"),
           rule("quadrature 'nodal'", "coulomb is nodal contact on the condensed stiffness", method="coulomb",
                quadrature=("gauss", "segment", "simpson")),
           rule("degree 1", "coulomb condenses onto the contact vertices", method="coulomb", degree=2),
           rule("model 'linear'", "coulomb condenses a constant stiffness", method="coulomb",
                model=("neohookean", "neohookean-mixed")),
           rule("geometry 'cartesian' (or another method)", "coulomb's contact vertices carry unweighted nodal "
                "areas (no 2 pi r)", method="coulomb", geometry="axisymmetric"),
           rule("solver 'direct'", "coulomb factors the stiffness itself (MUMPS)", method="coulomb",
                solver=("iterative", "inexact")),
           rule("sliding 'small'", "coulomb pairs once in the reference configuration and keeps the pairs (small "
                "sliding)", kind="two-body", method="coulomb", sliding="finite")))
