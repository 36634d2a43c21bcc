"""Symmetric Nitsche: ``p = <gamma g - P_n(u)>``, ``gamma = gamma0 E / h``."""
from ..laws import Nitsche
from .lagrange import mixed_models
from .spec import Method, Parameter, Sweep, rule

__all__ = ["METHOD"]

METHOD = Method(
    name="nitsche", summary="symmetric Nitsche, gamma = gamma0 E / h", law=Nitsche,
    parameters=(Parameter("gamma0", "gamma0", "gamma = gamma0 E / h (dimensionless)", default=10.0),),
    rigid="fenics_contact.methods.builders:nitsche_surface", two_body=None,
    no_two_body="nitsche needs the obstacle's stress-free side",
    sweep=Sweep("gamma0", "gamma0", colour="tab:purple", size=9.0, reference=True),
    rules=(rule("model 'linear' or 'neohookean' (or another method)", "Nitsche's surface stress P(u) N would need "
                "a mixed model's pressure field", method="nitsche", model=mixed_models()),
           rule("degree 1, model 'linear' or another method", "Nitsche's gamma = gamma0 E / h does not grow with "
                "the degree (coercivity needs ~p^2): on quadratic elements at finite strain gamma0 = 10 loses the "
                "solve (found by the full grid)", method="nitsche", degree=2, model="neohookean"),))
