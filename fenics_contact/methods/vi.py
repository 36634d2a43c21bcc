"""SNES VI: exact nodal ``g <= 0`` as bounds on the unknowns."""
from ..laws import SnesVI
from .spec import Method, Sweep, rule

__all__ = ["METHOD"]

METHOD = Method(
    name="vi", summary="exact nodal g <= 0 as bounds, PETSc SNES VI", law=SnesVI,
    rigid="fenics_contact.methods.builders:bound_surface", two_body=None,
    no_two_body="vi bounds one displacement component against a flat obstacle",
    sweep=Sweep("once", None, colour="tab:red", size=7.0, reference=True),
    rules=(rule("an axis-aligned half-plane (or another method)",
                "vi bounds the displacement component along an axis-aligned normal",
                method="vi", obstacle=("plane", "curved")),
           rule("quadrature 'nodal' and degree 1", "vi bounds the nodal displacement", method="vi",
                quadrature=("gauss", "segment", "simpson")),
           rule("degree 1", "vi's pressure is the nodal reaction over the vertex weight (0 at a mid-side node)",
                method="vi", degree=2),
           rule("geometry 'cartesian' (or another method)", "vi's pressure is the nodal reaction (a ring total) "
                "over vertex weights without the ring's 2 pi r", method="vi", geometry="axisymmetric"),
           rule("solver 'direct'", "SNES VI's reduced system changes size between iterations: GAMG cannot follow",
                method="vi", solver=("iterative", "inexact"))))
