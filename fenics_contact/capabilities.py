"""The capability matrix: which combinations of options the suite supports, declared once as data.

Axes (:func:`axes`): contact method (the registered methods of :mod:`fenics_contact.methods`), contact kind (a rigid
obstacle, two deformable bodies, or ``self``: a surface against itself), contact quadrature, passes (two-body),
dimension, displacement degree, bulk model, linear solver, friction, geometry (cartesian: 3D, plane strain or
stress; axisymmetric: the meridian section
of a body of revolution, every integral weighted by ``2 pi r``). Every combination is supported unless a rule of
:func:`rules` refuses it; a rule names the axis values it refuses and what to use instead. A method's own rules are
part of its declaration; the rules that follow from what it declares (no two-body surface, no friction) and the
rules of no single method are here. :func:`check` raises :class:`UnsupportedCombination` (a ``ValueError``) with one
line naming the combination; the entry points (:func:`fenics_contact.factory.contact_surface`,
:func:`fenics_contact.factory.two_body_surfaces`, :func:`fenics_contact.multipliers.unknown`, the scenes that
combine options) call it before any
assembly. ``python -m fenics_contact.capabilities`` prints the matrix (``docs/capabilities.md``).

Axis value ``None`` in :func:`check` means "not known here" (e.g. the linear solver when a surface is
built): rules on that axis are skipped, so an entry point refuses only what it can see.
"""
from __future__ import annotations

import itertools
from typing import Any, Iterator, Mapping

from . import methods as _methods
from .methods.spec import Rule, rule
from .models import MODELS

MIXED_MODELS = tuple(name for name, cls in MODELS.items() if cls.mixed)  # the unknown is (displacement, pressure)

__all__ = ["AXES", "MIXED_MODELS", "Rule", "UnsupportedCombination", "axes", "cells", "cells_like", "check", "describe",
           "markdown", "of", "refusal", "rules", "supported"]

_FIXED_AXES: dict[str, tuple] = {
    "kind": ("rigid", "two-body", "self"),  # self: a surface against itself (and the rest of its body)
    "obstacle": ("aligned", "plane", "curved", "none"),  # Obstacle.shape; two bodies: none
    "quadrature": ("nodal", "gauss", "segment", "simpson"),
    "passes": ("one", "two"),
    "dim": (2, 3),
    "degree": (1, 2),
    "model": tuple(MODELS),
    # iterative: Krylov with multigrid to a fixed tolerance; inexact: the same with each Krylov tolerance following
    # the Newton residual (Eisenstat-Walker, PETSc's snes_ksp_ew: INEXACT_NEWTON, the demos' --inexact)
    "solver": ("direct", "iterative", "inexact"),
    "friction": (False, True),
    "geometry": ("cartesian", "axisymmetric"),
    "sliding": ("finite", "small"),  # two-body contact kinematics: current configuration, or linearized
}


class _Axes(Mapping):
    """Axis name -> its values; the method axis is read from the registry when asked, so a method registered
    later is on the grid too."""

    def __getitem__(self, axis: str) -> tuple:
        return tuple(_methods.names()) if axis == "method" else _FIXED_AXES[axis]

    def __iter__(self) -> Iterator[str]:
        return iter(("method", *_FIXED_AXES))

    def __len__(self) -> int:
        return 1 + len(_FIXED_AXES)


AXES: Mapping[str, tuple] = _Axes()


def axes() -> dict[str, tuple]:
    """The axes with their values now (the registered methods included)."""
    return dict(AXES)


class UnsupportedCombination(ValueError):
    """A combination of options the suite refuses (one line: the combination and what to use instead)."""


# Rules of no single method. Ordered: the first matching rule gives the message.
_KIND = (
    rule("an obstacle (HalfPlane, Ball, Cylinder, Sphere)", "a rigid contact is against an obstacle",
         kind="rigid", obstacle="none"),
    rule("obstacle 'none'", "two deformable bodies have no rigid obstacle", kind="two-body",
         obstacle=("aligned", "plane", "curved")),
    rule("passes 'one'", "a rigid obstacle is never a slave: passes are a two-body option",
         kind="rigid", passes="two"),
    rule("quadrature 'nodal' or 'gauss'", "segment-to-segment integration pairs two meshed surfaces",
         kind="rigid", quadrature="segment"),
)
_SELF = (
    rule("passes 'two'", "a surface against itself is both sides of each contact: every point is a slave at weight "
         "1/2, the unbiased two-pass form", kind="self", passes="one"),
    rule("quadrature 'nodal', 'gauss' or 'simpson'", "self-contact pairs points, not segments", kind="self",
         quadrature="segment"),
    rule("sliding 'finite'", "a fold's pairs are found in the current configuration", kind="self", sliding="small"),
    rule("kind 'two-body' or mu 0", "self-contact is frictionless", kind="self", friction=True),
)
_GEOMETRY = (
    rule("dim 2 (the meridian section (r, z))", "an axisymmetric body is modelled on its 2D meridian section",
         geometry="axisymmetric", dim=3),
    rule("quadrature 'nodal' or 'gauss'", "the segment-to-segment element integrates without the ring's 2 pi r",
         geometry="axisymmetric", quadrature="segment"),
)
_TWO_BODY_FRICTION = (
    rule("quadrature 'nodal' or 'gauss' (pointwise two-body friction) or mu 0",
         "the segment-to-segment element has no tangential law", kind="two-body", friction=True,
         quadrature="segment"),
    rule("degree 1 (flat facets) or mu 0", "two-body friction projects the slip on flat master facets",
         kind="two-body", friction=True, degree=2),
)
_SLIDING = (
    rule("linearized=True (a rigid obstacle's small-displacement gap)", "sliding is a two-body option",
         kind="rigid", sliding="small"),
    rule("sliding 'finite'", "segment-to-segment integration clips the current facets", sliding="small",
         quadrature="segment"),
    rule("sliding 'finite' (or degree 1)", "the small-sliding gap is written on flat facets", sliding="small",
         degree=2),
    rule("sliding 'finite' (or the linear material)", "small sliding linearizes the contact kinematics, as the "
         "linear material linearizes the bulk's", sliding="small", model=tuple(m for m in MODELS if m != "linear")),
)
_QUADRATURE = (
    rule("degree 1 (or 2D)", "quadratic master facets are curved segments: 2D only", kind="two-body", degree=2,
         dim=3),
    rule("quadrature 'simpson'", "a quadratic two-body surface works at the three nodes of its facets (the vertex "
         "rule leaves the mid-side node without contact: the point_values IndexError)",
         kind="two-body", degree=2, quadrature=("nodal", "gauss")),
    rule("quadrature 'gauss' (or 'simpson' in 2D)",
         "the vertex rule leaves the mid-side nodes of quadratic facets without contact", degree=2,
         quadrature="nodal"),
    rule("quadrature 'nodal' or 'gauss'", "Simpson's rule uses the three nodes of a quadratic 2D facet",
         degree=1, quadrature="simpson"),
    rule("quadrature 'gauss' (3D)", "Simpson's rule uses the three nodes of a quadratic 2D facet",
         dim=3, quadrature="simpson"),
    rule("degree 1 or quadrature 'simpson'", "segment-to-segment integration clips flat facets",
         degree=2, quadrature="segment"),
)


_MIXED = (
    rule("degree 2", "the mixed model's unknown is Taylor-Hood: P2 displacement, P1 pressure (equal orders are not "
         "inf-sup stable)", model=MIXED_MODELS, degree=1),
    rule("solver 'direct'", "the mixed model's Jacobian is a saddle point (no near-nullspace of the pressure "
         "field for algebraic multigrid)", model=MIXED_MODELS, solver=("iterative", "inexact")),
)


_RULES: tuple | None = None  # (the registered methods, their rules): the grid asks for every cell


def rules() -> tuple[Rule, ...]:
    """Every rule, in the order they are tried: the kind, the geometry, the methods without self-contact or
    two-body surfaces, self-contact, two-body friction, the methods without friction, each method's own rules
    (registry order), the mixed model, quadrature and degree; every two-body rule refuses self-contact too."""
    global _RULES
    ms = tuple(_methods.methods())
    if _RULES is None or len(_RULES[0]) != len(ms) or any(a is not b for a, b in zip(_RULES[0], ms)):
        _RULES = ms, _rules(ms)  # holding the methods: no other object can take their ids
    return _RULES[1]


def _rules(ms: tuple) -> tuple[Rule, ...]:
    """:func:`rules` of the methods ``ms``."""
    two_body = [m.name for m in ms if m.two_body is not None]
    with_friction = [m.name for m in ms if m.friction != "none"]
    no_two_body = tuple(rule(f"method {', '.join(two_body[:-1])} or {two_body[-1]}",
                             m.no_two_body or f"{m.name} has no two-body surface", kind="two-body", method=m.name)
                        for m in ms if m.two_body is None)
    frictionless = tuple(m.name for m in ms if m.friction == "none")
    with_self = [m.name for m in ms if m.self_contact is not None]
    no_self = tuple(rule(f"method {', '.join(with_self[:-1])} or {with_self[-1]}", f"{m.name} has no self-contact "
                         "surface", kind="self", method=m.name) for m in ms if m.self_contact is None)
    no_friction = (rule(f"a method with friction ({', '.join(with_friction)}) or mu 0",
                        "these methods have no tangential law", friction=True, method=frictionless),) if frictionless \
        else ()
    own = tuple(r for m in ms for r in m.rules)
    every = (_KIND + _GEOMETRY + no_self + no_two_body + _SELF + _TWO_BODY_FRICTION + no_friction + own + _MIXED
             + _SLIDING + _QUADRATURE)
    return tuple(_also_self(r) for r in every)


def _also_self(r: Rule) -> Rule:
    """A two-body rule refuses self-contact too: a surface against itself is a two-body surface whose master is its
    own slave."""
    kinds = r.when.get("kind", ())
    if "two-body" not in kinds or "self" in kinds:
        return r
    return Rule({**r.when, "kind": kinds + ("self",)}, r.use, r.why)


def _fmt(axis: str, value: Any) -> str:
    if axis == "dim":
        return f"{value}D"
    if axis == "degree":
        return f"P{value}"
    if axis == "friction":
        return "friction" if value else "frictionless"
    if axis == "passes":
        return f"{value}-pass"
    if axis == "solver":
        return f"{value} solver"
    if axis == "obstacle":
        return {"aligned": "axis-aligned half-plane", "plane": "inclined half-plane", "curved": "curved obstacle",
                "none": "no obstacle"}[value]
    if axis == "quadrature":
        return f"{value} quadrature"
    if axis == "geometry":
        return f"{value} geometry"
    if axis == "sliding":
        return f"{value} sliding"
    return str(value)


def describe(**combo: Any) -> str:
    """The combination as words, axes in :data:`AXES` order (unknown axes left out)."""
    return ", ".join(_fmt(a, combo[a]) for a in AXES if combo.get(a) is not None)


def _validate(combo: Mapping[str, Any]) -> None:
    now = axes()
    for axis, value in combo.items():
        if axis not in now:
            raise ValueError(f"unknown capability axis {axis!r}; accepted: {', '.join(now)}")
        if value is not None and value not in now[axis]:
            raise ValueError(f"{axis} must be one of {now[axis]}, got {value!r}")


def refusal(**combo: Any) -> Rule | None:
    """The first rule that refuses ``combo`` (axes given as keywords; missing or ``None``: unknown), or None."""
    _validate(combo)
    for r in rules():
        if all(combo.get(a) is not None and combo[a] in vals for a, vals in r.when.items()):
            return r
    return None


def supported(**combo: Any) -> bool:
    """True if no rule refuses ``combo``."""
    return refusal(**combo) is None


def check(method: str | None = None, kind: str | None = None, quadrature: str | None = None,
          passes: str | None = None, dim: int | None = None, degree: int | None = None,
          model: str | None = None, solver: str | None = None, friction: bool | None = None,
          obstacle: str | None = None, geometry: str | None = None, sliding: str | None = None) -> None:
    """Raise :class:`UnsupportedCombination` (one line: the refused axis values, the whole combination and
    what to use instead) if a rule refuses the combination; ``None``: the axis is not known here."""
    combo = dict(method=method, kind=kind, quadrature=quadrature, passes=passes, dim=dim, degree=degree,
                 model=model, solver=solver, friction=friction, obstacle=obstacle, geometry=geometry, sliding=sliding)
    found = refusal(**combo)
    if found is not None:
        refused = describe(**{a: combo[a] for a in found.when})
        raise UnsupportedCombination(f"unsupported combination {refused} ({describe(**combo)}): {found.why}; "
                                     f"use {found.use}")


def of(law, u=None, material=None) -> dict:
    """The axis values an entry point can see: ``method`` and ``friction`` from the law, ``dim`` and ``degree``
    from the unknown ``u`` (a displacement or mixed (displacement, pressure) Function), ``model`` from the
    bulk material and ``geometry`` from its ``axisymmetric`` (``None`` where not given). A law of the user's own
    that no registered method declares has method ``None``: the rules on the method are skipped for it."""
    method = _methods.of_law(law)
    out = {"method": None if method is None else method.name, "friction": bool(law.has_friction)}
    if u is not None:
        V = u.function_space
        Vd = V.sub(0) if V.num_sub_spaces > 0 and V.sub(0).num_sub_spaces > 0 else V  # mixed: the displacement
        out["dim"] = V.mesh.geometry.dim
        out["degree"] = 2 if len(Vd.dofmap.dof_layout.entity_dofs(1, 0)) else 1  # Lagrange: edge dofs from P2
    if material is not None:
        out["model"] = material.model  # per-body Materials: linear if every body is
        out["geometry"] = "axisymmetric" if getattr(material, "axisymmetric", False) else "cartesian"
    return out


def cells() -> Iterator[dict]:
    """Every cell of the matrix (the product of :data:`AXES`), as keyword dictionaries."""
    grid = axes()
    for values in itertools.product(*grid.values()):
        yield dict(zip(grid, values))


def markdown() -> str:
    """The matrix as Markdown: the axes, the refusal rules, and the supported structural combinations per
    method (kind, quadrature, passes, dimension, degree) with the obstacles, models, solvers and friction they
    allow."""
    lines = ["# Capability matrix", "",
             "Generated by `python -m fenics_contact.capabilities > docs/capabilities.md` from the method "
             "declarations (`fenics_contact/methods/`) and `fenics_contact/capabilities.py` (what `check` uses); "
             "do not edit.", "",
             "Every combination of the axes is supported unless a rule below refuses it; a refused "
             "combination raises `UnsupportedCombination` (a `ValueError`) before any assembly, with one "
             "line naming it and what to use instead. `tests/test_capabilities.py` solves the supported "
             "cells on tiny meshes against closed forms and checks every refusal.", "", "## Axes", ""]
    for axis, values in axes().items():
        shown = (_fmt(axis, v) if axis in ("dim", "degree") else str(v) for v in values)
        lines.append(f"- **{axis}**: {', '.join(shown)}")
    lines += ["", "## Refused combinations", "", "| refused when | why | use instead |", "|---|---|---|"]
    for r in rules():
        when = "; ".join(f"{a} {' or '.join(str(v) for v in vals)}" for a, vals in r.when.items())
        lines.append(f"| {when} | {r.why} | {r.use} |")
    lines += ["", "## Supported combinations", "",
              "Per method and contact kind: the supported (quadrature, passes, dim, degree) cells, and for each "
              "the bulk models, linear solvers, friction settings and geometries it allows.", "",
              "| method | kind | quadrature | passes | dim | degree | obstacles | models | solvers | friction | "
              "geometries |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    structural = ("quadrature", "passes", "dim", "degree")
    for method in axes()["method"]:
        for kind in AXES["kind"]:
            for values in itertools.product(*(AXES[a] for a in structural)):
                s = dict(zip(structural, values), method=method, kind=kind)
                ok = [c for c in cells_like(s) if supported(**c)]
                if not ok:
                    continue
                col = {a: sorted({str(c[a]) if a != "friction" else ("yes" if c[a] else "no") for c in ok})
                       for a in ("obstacle", "model", "solver", "friction", "geometry")}
                lines.append(f"| {method} | {kind} | {s['quadrature']} | {s['passes']} | {s['dim']}D | "
                             f"P{s['degree']} | {', '.join(col['obstacle'])} | {', '.join(col['model'])} | "
                             f"{', '.join(col['solver'])} | {', '.join(col['friction'])} | "
                             f"{', '.join(col['geometry'])} |")
    return "\n".join(lines) + "\n"


def cells_like(fixed: Mapping[str, Any]) -> Iterator[dict]:
    """Every cell with the axis values of ``fixed``."""
    grid = axes()
    free = [a for a in grid if a not in fixed]
    for values in itertools.product(*(grid[a] for a in free)):
        yield {**fixed, **dict(zip(free, values))}


if __name__ == "__main__":
    import sys

    sys.stdout.write(markdown())
