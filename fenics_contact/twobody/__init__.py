"""Two deformable bodies in one mesh: closest-point pairing, mirror fields, coupling (formulation 1.4).

A *slave* and a *master* surface are facet tags of the same dolfinx mesh. Every slave contact point ``x_s =
X + u`` (vertices with ``nodal`` quadrature, Gauss points with ``gauss``, the three nodes of a quadratic
facet) is paired with the closest point of the master's **current** surface; the normal gap (positive =
penetration) is written in UFL against *mirror* fields on the slave side, which hold the paired master facet,
and the master dofs enter through the sparse operator ``I`` with ``w = I u``. The parts, one job each:

- :mod:`~.facets`: the slave and master facets (nodes, dofs, orientation) and the slave points;
- :mod:`~.exchange`: the master facets each rank needs, sent by their owners (parallel);
- :mod:`~.pairing`: projection of the slave points, hysteresis, rejection of exploded iterates;
- :mod:`~.mirror`: the mirror fields and the UFL gap against them;
- :mod:`~.coupling`: ``I``, the coupling blocks of residual and tangent, the Dirichlet columns;
- :mod:`~.report`: pressures and point tables at the slave points, timings;
- :mod:`~.surface`: :class:`TwoBodySurface`, which composes them.

Self-contact (:func:`fenics_contact.factory.self_contact_surfaces`) is a :class:`TwoBodySurface` whose slave surface
is its own master (``self_contact=True``): :mod:`~.pairing` leaves out each point's own neighbourhood.

The enforcements built on these parts: :mod:`~.friction` (Coulomb friction by return mapping), :mod:`~.nitsche`
(Nitsche's stress term), :mod:`~.nitsche_friction` (both); segment-to-segment integration (:mod:`mortar`) is built on
the same parts. Flat facets: segments (2D), triangles (3D); quadratic: curved segments (2D).
"""
from .coupling import JacobianPattern, MirrorCoupling, dirichlet_columns, interpolation_operator
from .exchange import LEAVES, MARGIN, MasterExchange, leaf_boxes
from .facets import POINT_RULES, FacetData, SlavePoints, facet_pair
from .mirror import MirrorFields, MirrorObstacle, barycentric, ufl_normal
from .pairing import Pairing
from .report import PointReport, Timings
from .surface import PASSES, QUADRATURES, SLIDING, TwoBodySurface

__all__ = ["LEAVES", "MARGIN", "PASSES", "QUADRATURES", "SLIDING", "POINT_RULES", "FacetData", "SlavePoints",
           "facet_pair", "MasterExchange", "leaf_boxes", "Pairing", "MirrorFields", "MirrorObstacle", "barycentric",
           "ufl_normal", "MirrorCoupling", "JacobianPattern", "dirichlet_columns", "interpolation_operator",
           "PointReport", "Timings", "TwoBodySurface"]
