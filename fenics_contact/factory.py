"""The contact surface a method needs, rigid or two-body: one constructor function per kind of contact.

Each reads the law's method declaration (:mod:`fenics_contact.methods`): the capability grid is checked first
(:mod:`fenics_contact.capabilities`), then the method's own surface builder is called. A law of one's own that
no method declares gets the surfaces of a law of the gap (``F(g)``).
"""
from __future__ import annotations

from typing import Callable

from dolfinx import fem

from . import methods
from .capabilities import check, of
from .laws import ContactLaw
from .materials import Material
from .methods.builders import law_self, law_surface, law_two_body
from .obstacles import Obstacle
from .surface import Surface
from .twobody import PASSES, QUADRATURES, SLIDING

__all__ = ["contact_surface", "two_body_surfaces", "two_body_multipliers", "self_contact_surfaces"]


def contact_surface(u: fem.Function, facet_tags, tag: int, obstacle: Obstacle, law: ContactLaw,
                    load: fem.Constant, quadrature: str = "nodal", name: str = "contact", linearized: bool = False,
                    material: Material | None = None) -> Surface:
    """The contact surface a law needs: a :class:`ContactSurface` for a law, a
    :class:`~fenics_contact.friction.FrictionalContact` for a law with friction, a
    :class:`~fenics_contact.bounds.BoundContact` for method ``vi``, a
    :class:`~fenics_contact.multipliers.MultiplierContact` for method ``lagrange`` (``u`` then the mixed
    unknown of :func:`~fenics_contact.multipliers.unknown`), a :class:`~fenics_contact.condensed.CondensedContact`
    for method ``coulomb`` (whose gap is linearized by construction; its steps are solved by the
    :class:`~fenics_contact.condensed.CondensedCoulomb` given to the problem), or a
    :class:`~fenics_contact.nitsche.NitscheContact` for method ``nitsche`` (which needs the bulk ``material``).
    ``linearized``: the small-displacement gap (see :class:`ContactSurface`). A combination the capability matrix
    refuses raises :class:`~fenics_contact.capabilities.UnsupportedCombination` before any assembly.

    Args:
        u: the problem's unknown: the displacement, or the mixed unknown of :func:`unknown` (method ``lagrange``).
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        tag: the contact boundary: a tag value, or a region name of ``facet_tags``.
        obstacle: the rigid :class:`Obstacle`.
        law: the method's law (:func:`make_law`).
        load: the load parameter ``t`` (a scalar ``Constant``); the obstacle moves by ``t * motion``.
        quadrature: the surface's rule: ``nodal``, ``gauss`` or ``simpson`` (the capability grid says which).
        name: the surface's name, in messages and output.
        linearized: the small-displacement gap ``g(X) - n(X) . u`` (normal at the reference point) instead of the
            gap of the current position ``X + u``.
        material: the bulk material (needed by ``nitsche``; ignored otherwise).

    Returns:
        The surface (a :class:`Surface`), to pass to :class:`ContactProblem`.
    """
    check(**of(law, u, material), kind="rigid", quadrature=quadrature, passes="one", obstacle=obstacle.shape)
    method = methods.of_law(law)
    build = law_surface if method is None else method.build_rigid
    return build(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized, material)


def two_body_surfaces(u: fem.Function, facet_tags, tag_a: int, tag_b: int, law_factory: Callable[[], ContactLaw],
                      load: fem.Constant, quadrature: str = "nodal", passes: str = "one", radius: float | None = None,
                      name: str = "twobody", work_quadrature: str | None = None,
                      cls: type | None = None, material: Material | None = None,
                      sliding: str | None = None) -> list[Surface]:
    """One-pass (``tag_a`` slave on ``tag_b``) or two-pass (each side slave once, weight 1/2) surfaces.
    ``law_factory()`` returns a fresh law for each surface. ``quadrature``: ``nodal``, ``gauss`` (pointwise
    at the slave points; ``simpson`` too for quadratic facets) or ``segment`` (segment-to-segment integration,
    2D and 3D, :mod:`~fenics_contact.mortar`); method ``coulomb`` (a :class:`~fenics_contact.laws.ExactCoulomb` law):
    one :class:`~fenics_contact.condensed.CondensedTwoBody` (2D, P1, nodal, one pass; its steps are solved by the
    step solver of :func:`~fenics_contact.condensed.step_solver_for`, given to the problem). Two-pass: every slave
    point of both passes, each at weight 1/2 (quadratic facets: a second-pass point that coincides with a
    first-pass one in the reference configuration is left out). ``cls``: the surface class of the pointwise
    quadratures (default :class:`TwoBodySurface`, or
    :class:`~fenics_contact.twobody.friction.FrictionalTwoBodySurface` for a law with friction). ``material``:
    the bulk material, which method ``nitsche`` needs (:class:`~fenics_contact.twobody.nitsche.NitscheTwoBody`,
    with ``segment`` :class:`~fenics_contact.mortar.NitscheSegmentSurface` (2D); two passes: the unbiased
    variant). A combination the capability matrix refuses raises
    :class:`~fenics_contact.capabilities.UnsupportedCombination` before any assembly.

    Args:
        u: the problem's unknown: the displacement, or the mixed unknown of :func:`unknown` (method ``lagrange``).
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        tag_a: the slave surface of the first pass: a tag value, or a region name.
        tag_b: the master surface of the first pass (likewise).
        law_factory: a callable returning a fresh law for each surface (``lambda: fc.make_law(...)``).
        load: the load parameter ``t`` (a scalar ``Constant``).
        quadrature: ``nodal``, ``gauss``, ``simpson`` (quadratic facets) or ``segment``.
        passes: ``one`` or ``two``.
        radius: the search radius (length; default twice the longest master facet); farther points have no pair.
        name: the surface's name, in messages and output.
        work_quadrature: the rule of the pressure's work term, if not ``quadrature``.
        cls: the surface class of the pointwise quadratures (None: chosen from the law).
        material: the bulk material (method ``nitsche``; else not used).
        sliding: ``finite`` (the current configuration; the pointwise surfaces' default) or ``small`` (pairs,
            weights and normals of the reference configuration, a gap linear in the displacements; flat facets,
            the linear material; method ``coulomb`` is small sliding by construction); None: the method's own.

    Returns:
        The surfaces (one per pass), to pass to :class:`ContactProblem`.
    """
    if passes not in PASSES:
        raise ValueError(f"passes must be one of {PASSES}, got {passes!r}")
    if quadrature not in QUADRATURES + ("simpson",):
        raise ValueError(f"contact quadrature must be one of {QUADRATURES + ('simpson',)}, got {quadrature!r}")
    if sliding not in SLIDING + (None,):
        raise ValueError(f"sliding must be one of {SLIDING}, got {sliding!r}")
    if not callable(law_factory):
        raise ValueError(f"law_factory must be a callable returning a fresh law for each surface "
                         f"(lambda: fc.make_law(...)), got {type(law_factory).__name__} {law_factory!r}")
    # The capability matrix (multipliers: the rule of the work term is the option; the constraint is nodal).
    probe = law_factory()
    check(**of(probe, u, material), kind="two-body", quadrature=work_quadrature or quadrature, passes=passes,
          obstacle="none", sliding=sliding)
    method = methods.of_law(probe)
    build = law_two_body if method is None else method.build_two_body
    return build(u, facet_tags, tag_a, tag_b, law_factory, load, quadrature, passes, radius, name, work_quadrature,
                 cls, material, sliding)


def two_body_multipliers(w: fem.Function, facet_tags, slave_tag: int, master_tag: int, law: ContactLaw,
                         load: fem.Constant, radius: float | None = None, name: str = "twobody",
                         passes: str = "one", work_quadrature: str | None = None) -> list[Surface]:
    """Two-body contact with the slave pressure as an unknown: nodal Signorini conditions of the slave
    vertices against the current master facets (:mod:`~fenics_contact.twobody`'s projection and coupling).
    ``passes="two"``: each surface slave once (weight 1/2), a pressure on both surfaces. Quadratic
    displacements: the constraint at the end nodes of each slave facet, the pressure P1 (linear along the
    facet) and its work integrated with ``work_quadrature`` (``simpson``: the two-point element).

    Args:
        w: the mixed unknown of :func:`unknown` (method ``lagrange``).
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        slave_tag: the slave surface: a tag value, or a region name of ``facet_tags``.
        master_tag: the master surface (likewise).
        law: a :class:`LagrangeMultiplier` (or :class:`PenaltyMultiplier`).
        load: the load parameter ``t`` (a scalar ``Constant``).
        radius: the search radius (length; default twice the longest master facet); farther points have no pair.
        name: the surface's name, in messages and output.
        passes: ``one`` or ``two``.
        work_quadrature: the rule of the pressure's work (quadratic facets: ``simpson``).

    Returns:
        The surfaces (one per pass).
    """
    return two_body_surfaces(w, facet_tags, slave_tag, master_tag, lambda: law,
                             load, "nodal", passes, radius, name, work_quadrature)


def self_contact_surfaces(u: fem.Function, facet_tags, tag: int | str, law_factory: Callable[[], ContactLaw],
                          load: fem.Constant, quadrature: str = "nodal", radius: float | None = None,
                          name: str = "self", material: Material | None = None) -> list[Surface]:
    """Self-contact: the surface ``tag`` against itself (and so against any other part of its body that ``tag``
    covers; :func:`~fenics_contact.domain.merge_regions` names a union), finite sliding, frictionless. Every point
    is paired with the closest point of the rest of the surface beyond its own neighbourhood (facets sharing its
    nodes, or facing the same way) and carries weight 1/2, so that each contact is counted once from each side
    (the unbiased two-pass form; Nitsche: each side with its own stress). A combination the capability matrix
    refuses (kind ``self``) raises :class:`~fenics_contact.capabilities.UnsupportedCombination` before any
    assembly.

    Args:
        u: the problem's unknown (a displacement, or a mixed (displacement, pressure) one).
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        tag: the surface: a tag value, or a region name.
        law_factory: a callable returning a fresh law (``lambda: fc.make_law(...)``).
        load: the load parameter ``t`` (a scalar ``Constant``).
        quadrature: ``nodal``, ``gauss`` or ``simpson`` (quadratic facets).
        radius: the search radius (length; default twice the longest facet); farther points have no pair.
        name: the surface's name, in messages and output.
        material: the bulk material (method ``nitsche``; else not used).

    Returns:
        The surfaces (one), to pass to :class:`ContactProblem`.
    """
    if quadrature not in QUADRATURES + ("simpson",):
        raise ValueError(f"contact quadrature must be one of {QUADRATURES + ('simpson',)}, got {quadrature!r}")
    probe = law_factory()
    check(**of(probe, u, material), kind="self", quadrature=quadrature, passes="two", obstacle="none",
          sliding="finite")
    method = methods.of_law(probe)
    build = law_self if method is None else method.build_self
    return build(u, facet_tags, tag, law_factory, load, quadrature, radius, name, material)
