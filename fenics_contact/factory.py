"""The contact surface a law needs, rigid or two-body: one constructor function per kind of contact.

This module imports every enforcement module (none of them imports it), so that the enforcement
modules never import each other back: :func:`contact_surface` (rigid obstacle),
:func:`two_body_surfaces` (pointwise or segment two-body contact), :func:`two_body_multipliers`
(two-body contact with the slave pressure as an unknown).
"""
from __future__ import annotations

import logging
from typing import Callable

from dolfinx import fem

from .bounds import BoundContact
from .capabilities import check, of
from .condensed import CondensedContact, CondensedTwoBody
from .contact import ContactSurface
from .friction import Friction, FrictionalContact
from .laws import ContactLaw, Coulomb, Exact, LagrangeMultiplier, NitscheLaw
from .materials import Material
from .mortar import SegmentSurface
from .multipliers import MultiplierContact, TwoBodyMultiplier
from .nitsche import NitscheContact
from .obstacles import Obstacle
from .twobody import PASSES, QUADRATURES, TwoBodySurface
from .twobody_friction import FrictionalTwoBodySurface

__all__ = ["contact_surface", "two_body_surfaces", "two_body_multipliers"]


def contact_surface(u: fem.Function, facet_tags, tag: int, obstacle: Obstacle, law: ContactLaw,
                    load: fem.Constant, quadrature: str = "nodal", name: str = "contact", linearized: bool = False,
                    material: Material | None = None) -> ContactSurface:
    """The contact surface a law needs: a :class:`ContactSurface` for a law, a
    :class:`~fenics_contact.friction.FrictionalContact` for a law with friction, a
    :class:`~fenics_contact.bounds.BoundContact` for method ``vi``, a
    :class:`~fenics_contact.multipliers.MultiplierContact` for method ``lagrange`` (``u`` then the mixed
    unknown of :func:`~fenics_contact.multipliers.unknown`), a :class:`~fenics_contact.condensed.CondensedContact`
    for method ``coulomb`` (whose gap is linearized by construction; its steps are solved by the
    :class:`~fenics_contact.condensed.CondensedCoulomb` given to the problem), or a
    :class:`~fenics_contact.nitsche.NitscheContact` for method ``nitsche`` (which needs the bulk ``material``).
    ``linearized``: the small-displacement gap (see :class:`ContactSurface`). A combination the capability matrix
    refuses raises :class:`~fenics_contact.capabilities.UnsupportedCombination` before any assembly."""
    check(**of(law, u, material), kind="rigid", quadrature=quadrature, passes="one")
    if isinstance(law, NitscheLaw):
        return NitscheContact(u, facet_tags, tag, obstacle, law, load, quadrature, name, material=material)
    if isinstance(law, Coulomb):
        return CondensedContact(u, facet_tags, tag, obstacle, law, load, quadrature, name)
    if isinstance(law, LagrangeMultiplier):
        if linearized:
            raise ValueError("method 'lagrange' enforces the current gap: linearized=True is not available")
        return MultiplierContact(u, facet_tags, tag, obstacle, law, load, quadrature, name)
    cls = BoundContact if isinstance(law, Exact) else FrictionalContact if isinstance(law, Friction) else ContactSurface
    return cls(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized)


def two_body_surfaces(u: fem.Function, facet_tags, tag_a: int, tag_b: int, law_factory: Callable[[], ContactLaw],
                      load: fem.Constant, quadrature: str = "nodal", passes: str = "one", radius: float | None = None,
                      name: str = "twobody", work_quadrature: str | None = None,
                      cls: type[TwoBodySurface] | None = None) -> list[TwoBodySurface]:
    """One-pass (``tag_a`` slave on ``tag_b``) or two-pass (each side slave once, weight 1/2) surfaces.
    ``law_factory()`` returns a fresh law for each surface. ``quadrature``: ``nodal``, ``gauss`` (pointwise
    at the slave points; ``simpson`` too for quadratic facets) or ``segment`` (segment-to-segment integration,
    2D and 3D, :mod:`~fenics_contact.mortar`); method ``coulomb`` (a :class:`~fenics_contact.laws.Coulomb` law):
    one :class:`~fenics_contact.condensed.CondensedTwoBody` (2D, P1, nodal, one pass; its steps are solved by the
    step solver of :func:`~fenics_contact.condensed.step_solver_for`, given to the problem). Two-pass: every slave
    point of both passes, each at weight 1/2 (quadratic facets: a second-pass point that coincides with a
    first-pass one in the reference configuration is left out). ``cls``: the surface class of the pointwise
    quadratures (default :class:`TwoBodySurface`, or
    :class:`~fenics_contact.twobody_friction.FrictionalTwoBodySurface` for a law with friction).
    A combination the capability matrix refuses raises
    :class:`~fenics_contact.capabilities.UnsupportedCombination` before any assembly."""
    if passes not in PASSES:
        raise ValueError(f"passes must be one of {PASSES}, got {passes!r}")
    if quadrature not in QUADRATURES + ("simpson",):
        raise ValueError(f"contact quadrature must be one of {QUADRATURES + ('simpson',)}, got {quadrature!r}")
    # The capability matrix (multipliers: the rule of the work term is the option; the constraint is nodal).
    probe = law_factory()
    check(**of(probe, u), kind="two-body", quadrature=work_quadrature or quadrature, passes=passes)
    if isinstance(probe, Coulomb):  # exact Coulomb on the condensed system (2D, P1, nodal, one pass)
        if cls is not None or work_quadrature is not None:
            raise ValueError("method 'coulomb' takes neither cls nor work_quadrature")
        return [CondensedTwoBody(u, facet_tags, tag_a, tag_b, law_factory(), load, radius, name)]
    if quadrature == "segment":
        if cls is not None or work_quadrature is not None:
            raise ValueError("quadrature 'segment' takes neither cls nor work_quadrature")
        if passes == "one":
            return [SegmentSurface(u, facet_tags, tag_a, tag_b, law_factory(), load, 1.0, radius, name)]
        return [SegmentSurface(u, facet_tags, tag_a, tag_b, law_factory(), load, 0.5, radius, f"{name}_a"),
                SegmentSurface(u, facet_tags, tag_b, tag_a, law_factory(), load, 0.5, radius, f"{name}_b")]
    cls = cls or (FrictionalTwoBodySurface if isinstance(probe, Friction) else TwoBodySurface)
    kw = {"work_quadrature": work_quadrature}
    if passes == "one":
        return [cls(u, facet_tags, tag_a, tag_b, law_factory(), load, quadrature, 1.0, radius, name, **kw)]
    # Flat facets: no node-on-node exclusion. A second-pass point left out where it coincides with a first-pass
    # point left that point alone at weight 1/2, i.e. half the force at the doubled pressure (+62 % p0 on the
    # axis of a two-body Hertz case where both meshes have a node); both points at weight 1/2 give the one-pass
    # force. Exact constraints (multipliers) would be duplicated there: two passes are refused for them
    # (capabilities). Quadratic facets (the sheet) keep the exclusion: its surface-locking figures use it.
    a = cls(u, facet_tags, tag_a, tag_b, law_factory(), load, quadrature, 0.5, radius, f"{name}_a", **kw)
    b = cls(u, facet_tags, tag_b, tag_a, law_factory(), load, quadrature, 0.5, radius, f"{name}_b",
            exclude=a.reference_points() if a.quadratic else None, **kw)
    left_out = b.comm.allreduce(int(b._excluded.sum()))
    if left_out and b.comm.rank == 0:  # not silent: the partner carries half the force there (see above)
        logging.getLogger(__name__).warning(
            "%s: %d second-pass points coincide with first-pass points on quadratic facets and are left out; "
            "their partners carry weight 1/2 (pressure there doubled)", name, left_out)
    return [a, b]


def two_body_multipliers(w: fem.Function, facet_tags, slave_tag: int, master_tag: int, law: LagrangeMultiplier,
                         load: fem.Constant, radius: float | None = None, name: str = "twobody",
                         passes: str = "one", work_quadrature: str | None = None) -> list[TwoBodyMultiplier]:
    """Two-body contact with the slave pressure as an unknown: nodal Signorini conditions of the slave
    vertices against the current master facets (:mod:`~fenics_contact.twobody`'s projection and coupling).
    ``passes="two"``: each surface slave once (weight 1/2), a pressure on both surfaces. Quadratic
    displacements: the constraint at the end nodes of each slave facet, the pressure P1 (linear along the
    facet) and its work integrated with ``work_quadrature`` (``simpson``: the two-point element)."""
    return two_body_surfaces(w, facet_tags, slave_tag, master_tag, lambda: law,
                             load, "nodal", passes, radius, name, work_quadrature, TwoBodyMultiplier)
