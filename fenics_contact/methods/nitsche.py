"""Nitsche: ``p = <gamma g - P_n(u)>``, ``gamma = gamma0 E / h``; ``theta`` 1 symmetric, 0 incomplete, -1
skew-symmetric; between two bodies unbiased with two passes (each side's own stress, weight 1/2), frictionless,
Tresca or Coulomb."""
from ..laws import Nitsche
from .lagrange import mixed_models
from .spec import Method, Parameter, Sweep, rule

__all__ = ["METHOD"]

METHOD = Method(
    name="nitsche", summary="Nitsche (symmetric, incomplete or skew), gamma = gamma0 E / h; two bodies: unbiased "
                            "with two passes", law=Nitsche,
    parameters=(Parameter("gamma0", "gamma0", "gamma = gamma0 E / h (dimensionless)", default=10.0),
                Parameter("theta", "nitsche_theta", "Nitsche's theta: 1 symmetric, 0 incomplete, -1 skew-symmetric",
                          range="sign", default=1.0)),
    rigid="fenics_contact.methods.builders:nitsche_surface",
    two_body="fenics_contact.methods.builders:nitsche_two_body",
    self_contact="fenics_contact.methods.builders:nitsche_self",
    friction="law", sweep=Sweep("gamma0", "gamma0", colour="tab:purple", size=9.0, reference=True),
    rules=(rule("model 'linear' or 'neohookean' (or another method)", "Nitsche's surface stress P(u) N would need "
                "a mixed model's pressure field", method="nitsche", model=mixed_models()),
           rule("kind 'two-body', mu 0 or another method", "Nitsche's friction is built between two bodies",
                method="nitsche", kind="rigid", friction=True),
           rule("degree 1, model 'linear' or another method", "Nitsche's gamma = gamma0 E / h does not grow with "
                "the degree (coercivity needs ~p^2): on quadratic elements at finite strain gamma0 = 10 loses the "
                "solve (found by the full grid)", method="nitsche", degree=2, model="neohookean"),
           rule("quadrature 'nodal' or 'gauss' (or dim 2)", "two-body Nitsche's segment-to-segment element is "
                "2D (the stress of P1 triangles)", method="nitsche", kind="two-body", quadrature="segment", dim=3),
           rule("degree 1 (or another method)", "two-body Nitsche is built and checked on flat (degree-1) facets",
                method="nitsche", kind="two-body", degree=2),
           rule("kind 'rigid' or geometry 'cartesian' (or another method)", "two-body Nitsche's stress terms carry "
                "no 2 pi r", method="nitsche", kind="two-body", geometry="axisymmetric")))
