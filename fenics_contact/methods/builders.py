"""The surfaces of the built-in methods, by contact kind: what a :class:`~fenics_contact.methods.spec.Method`
names as its ``rigid`` and ``two_body`` builders. The entry points (:mod:`fenics_contact.factory`) check the
capability grid first and then call the method's builder.

Rigid builders take ``(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized, material)``;
two-body builders ``(u, facet_tags, tag_a, tag_b, law_factory, load, quadrature, passes, radius, name,
work_quadrature, cls, material, sliding)`` and return a list of surfaces (``sliding`` None: the surface's
default); self-contact builders ``(u, facet_tags, tag, law_factory, load, quadrature, radius, name, material)``
and return a list of surfaces.
"""
from __future__ import annotations

import functools
import logging

from ..bounds import BoundContact
from ..condensed import CondensedContact, CondensedTwoBody
from ..contact import ContactSurface
from ..friction import Friction, FrictionalContact
from ..mortar import NitscheSegmentSurface, SegmentSurface
from ..multiplier_friction import MultiplierFrictionalContact, MultiplierFrictionalTwoBody
from ..multipliers import MultiplierContact, TwoBodyMultiplier
from ..nitsche import NitscheContact
from ..twobody import TwoBodySurface
from ..twobody.friction import FrictionalTwoBodySurface
from ..twobody.nitsche import NitscheTwoBody
from ..twobody.nitsche_friction import NitscheFrictionTwoBody

__all__ = ["law_surface", "bound_surface", "condensed_surface", "multiplier_surface", "nitsche_surface",
           "law_two_body", "condensed_two_body", "multiplier_two_body", "nitsche_two_body", "law_self", "nitsche_self"]


# --- rigid obstacle ---------------------------------------------------------------------------------------
def law_surface(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized, material):
    """A law of the gap ``F(g)`` (penalty-type): a :class:`ContactSurface`, or a :class:`FrictionalContact` for a
    :class:`~fenics_contact.friction.Friction` law."""
    cls = FrictionalContact if isinstance(law, Friction) else ContactSurface
    return cls(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized)


def bound_surface(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized, material):
    """SNES VI: bounds on the nodal displacement (:class:`BoundContact`)."""
    return BoundContact(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized)


def condensed_surface(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized, material):
    """Exact Signorini-Coulomb on the condensed stiffness (:class:`CondensedContact`; its gap is linearized by
    construction)."""
    return CondensedContact(u, facet_tags, tag, obstacle, law, load, quadrature, name)


def multiplier_surface(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized, material):
    """The pressure as an unknown (:class:`MultiplierContact`; ``u`` the mixed unknown of
    :func:`~fenics_contact.multipliers.unknown`); with friction the traction
    (:class:`~fenics_contact.multiplier_friction.MultiplierFrictionalContact`)."""
    if isinstance(law, Friction):
        return MultiplierFrictionalContact(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized)
    if linearized:
        raise ValueError(f"method {law.name!r} enforces the current gap: linearized=True is not available")
    return MultiplierContact(u, facet_tags, tag, obstacle, law, load, quadrature, name)


def nitsche_surface(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized, material):
    """Symmetric Nitsche (:class:`NitscheContact`; needs the bulk ``material``)."""
    return NitscheContact(u, facet_tags, tag, obstacle, law, load, quadrature, name, material=material)


# --- two deformable bodies ---------------------------------------------------------------------------------
def law_two_body(u, facet_tags, tag_a, tag_b, law_factory, load, quadrature, passes, radius, name, work_quadrature,
                 cls, material=None, sliding=None):
    """Pointwise (nodal, Gauss, Simpson) or segment-to-segment two-body surfaces of a law of the gap; one pass
    (``tag_a`` slave) or two (each side slave once, weight 1/2)."""
    if quadrature == "segment":
        if cls is not None or work_quadrature is not None:
            raise ValueError("quadrature 'segment' takes neither cls nor work_quadrature")
        if passes == "one":
            return [SegmentSurface(u, facet_tags, tag_a, tag_b, law_factory(), load, 1.0, radius, name)]
        return [SegmentSurface(u, facet_tags, tag_a, tag_b, law_factory(), load, 0.5, radius, f"{name}_a"),
                SegmentSurface(u, facet_tags, tag_b, tag_a, law_factory(), load, 0.5, radius, f"{name}_b")]
    probe = law_factory()
    cls = cls or (FrictionalTwoBodySurface if isinstance(probe, Friction) else TwoBodySurface)
    kw = {"work_quadrature": work_quadrature, **({} if sliding is None else {"sliding": sliding})}
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


def condensed_two_body(u, facet_tags, tag_a, tag_b, law_factory, load, quadrature, passes, radius, name,
                       work_quadrature, cls, material=None, sliding=None):
    """Exact Coulomb between two bodies on the condensed system (2D or 3D, P1, nodal, one pass): one
    :class:`CondensedTwoBody`."""
    if cls is not None or work_quadrature is not None:
        raise ValueError("method 'coulomb' takes neither cls nor work_quadrature")
    return [CondensedTwoBody(u, facet_tags, tag_a, tag_b, law_factory(), load, radius, name)]


def multiplier_two_body(u, facet_tags, tag_a, tag_b, law_factory, load, quadrature, passes, radius, name,
                        work_quadrature, cls, material=None, sliding=None):
    """The slave pressure as an unknown (:class:`TwoBodyMultiplier`): nodal Signorini conditions of the slave
    vertices against the current master facets; ``work_quadrature`` ``simpson`` on quadratic facets (the
    two-point element). With friction the slave traction
    (:class:`~fenics_contact.multiplier_friction.MultiplierFrictionalTwoBody`)."""
    friction = isinstance(law_factory(), Friction)
    return law_two_body(u, facet_tags, tag_a, tag_b, law_factory, load, "nodal", passes, radius, name,
                        work_quadrature, cls or (MultiplierFrictionalTwoBody if friction else TwoBodyMultiplier),
                        sliding=sliding)


def nitsche_two_body(u, facet_tags, tag_a, tag_b, law_factory, load, quadrature, passes, radius, name,
                     work_quadrature, cls, material=None, sliding=None):
    """Nitsche between two bodies (:class:`NitscheTwoBody`, with friction :class:`NitscheFrictionTwoBody`; needs
    the bulk ``material``): one pass (the slave's stress) or two (unbiased: each side slave once with its own
    stress, weight 1/2)."""
    if cls is not None:
        raise ValueError("method 'nitsche' takes no cls")
    if material is None:
        raise ValueError("method 'nitsche' needs the bulk material (material=...) for the surface stress")
    if quadrature == "segment":  # 2D, P1, frictionless (capabilities)
        if work_quadrature is not None:
            raise ValueError("quadrature 'segment' takes no work_quadrature")
        if passes == "one":
            return [NitscheSegmentSurface(u, facet_tags, tag_a, tag_b, law_factory(), load, 1.0, radius, name,
                                          material=material)]
        return [NitscheSegmentSurface(u, facet_tags, tag_a, tag_b, law_factory(), load, 0.5, radius, f"{name}_a",
                                      material=material),
                NitscheSegmentSurface(u, facet_tags, tag_b, tag_a, law_factory(), load, 0.5, radius, f"{name}_b",
                                      material=material)]
    cls = NitscheFrictionTwoBody if isinstance(law_factory(), Friction) else NitscheTwoBody
    return law_two_body(u, facet_tags, tag_a, tag_b, law_factory, load, quadrature, passes, radius, name,
                        work_quadrature, functools.partial(cls, material=material), sliding=sliding)


# --- a surface against itself ------------------------------------------------------------------------------
def law_self(u, facet_tags, tag, law_factory, load, quadrature, radius, name, material=None, cls=None):
    """Self-contact of a law of the gap: one :class:`TwoBodySurface` of ``tag`` against itself at weight 1/2
    (every contact seen from both of its sides: the unbiased two-pass form), finite sliding."""
    cls = cls or TwoBodySurface
    return [cls(u, facet_tags, tag, tag, law_factory(), load, quadrature, 0.5, radius, name, self_contact=True)]


def nitsche_self(u, facet_tags, tag, law_factory, load, quadrature, radius, name, material=None):
    """Nitsche's self-contact (:class:`NitscheTwoBody` of ``tag`` against itself at weight 1/2: each side of a
    contact with its own stress, the unbiased two-pass form; needs the bulk ``material``)."""
    if material is None:
        raise ValueError("method 'nitsche' needs the bulk material (material=...) for the surface stress")
    return law_self(u, facet_tags, tag, law_factory, load, quadrature, radius, name,
                    cls=functools.partial(NitscheTwoBody, material=material))
