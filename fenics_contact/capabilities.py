"""The capability matrix: which combinations of options the suite supports, declared once as data.

Axes (:data:`AXES`): contact method (:data:`fenics_contact.laws.METHODS`), contact kind (a rigid obstacle
or two deformable bodies), contact quadrature, passes (two-body), dimension, displacement degree, bulk
model, linear solver, friction. Every combination is supported unless a rule of :data:`RULES` refuses it;
a rule names the axis values it refuses and what to use instead. :func:`check` raises
:class:`UnsupportedCombination` (a ``ValueError``) with one line naming the combination; the entry points
(:func:`fenics_contact.bounds.contact_surface`, :func:`fenics_contact.twobody.two_body_surfaces`,
:func:`fenics_contact.multipliers.unknown`, the scenes that combine options) call it before any
assembly. ``python -m fenics_contact.capabilities`` prints the matrix (``docs/capabilities.md``).

Axis value ``None`` in :func:`check` means "not known here" (e.g. the linear solver when a surface is
built): rules on that axis are skipped, so an entry point refuses only what it can see.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any, Iterator, Mapping

from .laws import METHODS

__all__ = ["AXES", "RULES", "Rule", "UnsupportedCombination", "cells", "cells_like", "check", "describe",
           "markdown", "of", "refusal", "supported"]

MULTIPLIERS = ("lagrange", "penalty_multiplier")
LAWS = ("penalty", "cross", "auglag", "compliance")  # penalty-type laws: a pressure F(g), friction on top

AXES: dict[str, tuple] = {
    "method": tuple(METHODS),
    "kind": ("rigid", "two-body"),
    "quadrature": ("nodal", "gauss", "segment", "simpson"),
    "passes": ("one", "two"),
    "dim": (2, 3),
    "degree": (1, 2),
    "model": ("linear", "neohookean"),
    "solver": ("direct", "iterative"),
    "friction": (False, True),
}


class UnsupportedCombination(ValueError):
    """A combination of options the suite refuses (one line: the combination and what to use instead)."""


@dataclass(frozen=True)
class Rule:
    """Refuse every combination whose axis values are all in ``when`` (axis -> refused values); ``use``:
    what to use instead; ``why``: the reason, for the docs."""

    when: Mapping[str, tuple]
    use: str
    why: str


def _r(use: str, why: str, **when: Any) -> Rule:
    return Rule({k: tuple(v) if isinstance(v, (tuple, list)) else (v,) for k, v in when.items()}, use, why)


NON_LAW = ("vi", "coulomb", "nitsche") + MULTIPLIERS
# Ordered: the first matching rule gives the message (method-specific rules before the generic ones, so that
# the advice fits the method).
RULES: tuple[Rule, ...] = (
    # --- kind and passes
    _r("passes 'one'", "a rigid obstacle is never a slave: passes are a two-body option",
       kind="rigid", passes="two"),
    _r("quadrature 'nodal' or 'gauss'", "segment-to-segment integration pairs two meshed surfaces",
       kind="rigid", quadrature="segment"),
    _r("method penalty, cross, auglag, compliance, coulomb, lagrange or penalty_multiplier",
       "vi bounds one displacement component against a flat obstacle; nitsche needs the obstacle's stress-free "
       "side", kind="two-body", method=("vi", "nitsche")),
    _r("passes 'one'", "coulomb pairs each slave vertex once with the master surface (two passes would "
       "constrain each pair twice)", kind="two-body", method="coulomb", passes="two"),
    _r("quadrature 'nodal' or 'gauss' (pointwise two-body friction) or mu 0",
       "the segment-to-segment element has no tangential law", kind="two-body", friction=True,
       quadrature="segment"),
    _r("degree 1 (flat facets) or mu 0", "two-body friction projects the slip on flat master facets",
       kind="two-body", friction=True, degree=2),
    # --- friction
    _r("a method with friction (penalty, cross, auglag, compliance, coulomb) or mu 0",
       "these methods have no tangential law", friction=True, method=("vi", "nitsche") + MULTIPLIERS),
    # --- exact methods
    _r("quadrature 'nodal' and degree 1", "vi bounds the nodal displacement", method="vi",
       quadrature=("gauss", "segment", "simpson")),
    _r("degree 1", "vi's pressure is the nodal reaction over the vertex weight (0 at a mid-side node)",
       method="vi", degree=2),
    _r("solver 'direct'", "SNES VI's reduced system changes size between iterations: GAMG cannot follow",
       method="vi", solver="iterative"),
    _r("quadrature 'nodal'", "coulomb is nodal contact on the condensed stiffness", method="coulomb",
       quadrature=("gauss", "segment", "simpson")),
    _r("degree 1", "coulomb condenses onto the contact vertices", method="coulomb", degree=2),
    _r("dim 2", "coulomb has one tangential direction", method="coulomb", dim=3),
    _r("model 'linear'", "coulomb condenses a constant stiffness", method="coulomb", model="neohookean"),
    _r("solver 'direct'", "coulomb factors the stiffness itself (MUMPS)", method="coulomb", solver="iterative"),
    _r("quadrature 'nodal' (P1) or 'simpson' (P2)", "the multipliers' constraint sits at the vertices",
       method=MULTIPLIERS, quadrature=("gauss", "segment")),
    _r("degree 1", "the multipliers' quadratic (two-point) element is 2D", method=MULTIPLIERS, degree=2, dim=3),
    _r("quadrature 'simpson' (the two-point element)", "the vertex rule alone leaves the mid-side nodes of "
       "quadratic facets without the pressure's work", method=MULTIPLIERS, degree=2, quadrature="nodal"),
    _r("passes 'one'", "two passes of exact constraints over-constrain the surface (surface locking, "
       "a pressure split arbitrarily between the passes)", method=MULTIPLIERS, passes="two"),
    # --- quadrature and degree
    _r("degree 1 (or 2D)", "quadratic master facets are curved segments: 2D only", kind="two-body", degree=2, dim=3),
    _r("quadrature 'simpson'", "a quadratic two-body surface works at the three nodes of its facets (the vertex "
       "rule leaves the mid-side node without contact: the point_values IndexError)",
       kind="two-body", degree=2, quadrature=("nodal", "gauss")),
    _r("quadrature 'gauss' (or 'simpson' in 2D)",
       "the vertex rule leaves the mid-side nodes of quadratic facets without contact", degree=2, quadrature="nodal"),
    _r("quadrature 'nodal' or 'gauss'", "Simpson's rule uses the three nodes of a quadratic 2D facet",
       degree=1, quadrature="simpson"),
    _r("quadrature 'gauss' (3D)", "Simpson's rule uses the three nodes of a quadratic 2D facet",
       dim=3, quadrature="simpson"),
    _r("degree 1 or quadrature 'simpson'", "segment-to-segment integration clips flat facets",
       degree=2, quadrature="segment"),
    _r("method penalty, auglag or compliance", "the segment element's NumPy law fails on cross-constraints' open "
       "branch (a singular first tangent: MUMPS fails at the first iterate; found by the full grid)",
       kind="two-body", quadrature="segment", method="cross"),
    _r("degree 1, model 'linear' or another method", "Nitsche's gamma = gamma0 E / h does not grow with the degree "
       "(coercivity needs ~p^2): on quadratic elements at finite strain gamma0 = 10 loses the solve (found by the "
       "full grid)", method="nitsche", degree=2, model="neohookean"),
)


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
    if axis == "quadrature":
        return f"{value} quadrature"
    return str(value)


def describe(**combo: Any) -> str:
    """The combination as words, axes in :data:`AXES` order (unknown axes left out)."""
    return ", ".join(_fmt(a, combo[a]) for a in AXES if combo.get(a) is not None)


def _validate(combo: Mapping[str, Any]) -> None:
    for axis, value in combo.items():
        if axis not in AXES:
            raise ValueError(f"unknown capability axis {axis!r}; accepted: {', '.join(AXES)}")
        if value is not None and value not in AXES[axis]:
            raise ValueError(f"{axis} must be one of {AXES[axis]}, got {value!r}")


def refusal(**combo: Any) -> Rule | None:
    """The first rule that refuses ``combo`` (axes given as keywords; missing or ``None``: unknown), or None."""
    _validate(combo)
    for rule in RULES:
        if all(combo.get(a) is not None and combo[a] in vals for a, vals in rule.when.items()):
            return rule
    return None


def supported(**combo: Any) -> bool:
    """True if no rule refuses ``combo``."""
    return refusal(**combo) is None


def check(method: str | None = None, kind: str | None = None, quadrature: str | None = None,
          passes: str | None = None, dim: int | None = None, degree: int | None = None,
          model: str | None = None, solver: str | None = None, friction: bool | None = None) -> None:
    """Raise :class:`UnsupportedCombination` (one line: the refused axis values, the whole combination and
    what to use instead) if a rule refuses the combination; ``None``: the axis is not known here."""
    combo = dict(method=method, kind=kind, quadrature=quadrature, passes=passes, dim=dim, degree=degree,
                 model=model, solver=solver, friction=friction)
    rule = refusal(**combo)
    if rule is not None:
        refused = describe(**{a: combo[a] for a in rule.when})
        raise UnsupportedCombination(f"unsupported combination {refused} ({describe(**combo)}): {rule.why}; "
                                     f"use {rule.use}")


def of(law, u=None, material=None) -> dict:
    """The axis values an entry point can see: ``method`` and ``friction`` from the law, ``dim`` and ``degree``
    from the unknown ``u`` (a displacement or mixed (displacement, pressure) Function), ``model`` from the
    bulk material (``None`` where not given). A law of the user's own (a name not in ``METHODS``) has method
    ``None``: the rules on the method are skipped for it."""
    name = law.name
    friction = name.endswith("+friction") or (name == "coulomb" and float(law.mu) > 0.0)
    method = name.split("+")[0]
    out = {"method": method if method in METHODS else None, "friction": friction}  # a user's own law: unknown
    if u is not None:
        V = u.function_space
        Vd = V.sub(0) if V.num_sub_spaces > 0 and V.sub(0).num_sub_spaces > 0 else V  # mixed: the displacement
        out["dim"] = V.mesh.geometry.dim
        out["degree"] = 2 if len(Vd.dofmap.dof_layout.entity_dofs(1, 0)) else 1  # Lagrange: edge dofs from P2
    if material is not None:
        out["model"] = "linear" if material.linear else "neohookean"  # per-body Materials: linear if every body is
    return out


def cells() -> Iterator[dict]:
    """Every cell of the matrix (the product of :data:`AXES`), as keyword dictionaries."""
    for values in itertools.product(*AXES.values()):
        yield dict(zip(AXES, values))


def markdown() -> str:
    """The matrix as Markdown: the axes, the refusal rules, and the supported structural combinations per
    method (kind, quadrature, passes, dimension, degree) with the models, solvers and friction they allow."""
    lines = ["# Capability matrix", "",
             "Generated by `python -m fenics_contact.capabilities > docs/capabilities.md` from "
             "`fenics_contact/capabilities.py` (the same declaration `check` uses); do not edit.", "",
             "Every combination of the axes is supported unless a rule below refuses it; a refused "
             "combination raises `UnsupportedCombination` (a `ValueError`) before any assembly, with one "
             "line naming it and what to use instead. `tests/test_capabilities.py` solves the supported "
             "cells on tiny meshes against closed forms and checks every refusal.", "", "## Axes", ""]
    for axis, values in AXES.items():
        shown = (_fmt(axis, v) if axis in ("dim", "degree") else str(v) for v in values)
        lines.append(f"- **{axis}**: {', '.join(shown)}")
    lines += ["", "## Refused combinations", "", "| refused when | why | use instead |", "|---|---|---|"]
    for rule in RULES:
        when = "; ".join(f"{a} {' or '.join(str(v) for v in vals)}" for a, vals in rule.when.items())
        lines.append(f"| {when} | {rule.why} | {rule.use} |")
    lines += ["", "## Supported combinations", "",
              "Per method and contact kind: the supported (quadrature, passes, dim, degree) cells, and for each "
              "the bulk models, linear solvers and friction settings it allows.", "",
              "| method | kind | quadrature | passes | dim | degree | models | solvers | friction |",
              "|---|---|---|---|---|---|---|---|---|"]
    structural = ("quadrature", "passes", "dim", "degree")
    for method in AXES["method"]:
        for kind in AXES["kind"]:
            for values in itertools.product(*(AXES[a] for a in structural)):
                s = dict(zip(structural, values), method=method, kind=kind)
                ok = [c for c in cells_like(s) if supported(**c)]
                if not ok:
                    continue
                col = {a: sorted({str(c[a]) if a != "friction" else ("yes" if c[a] else "no") for c in ok})
                       for a in ("model", "solver", "friction")}
                lines.append(f"| {method} | {kind} | {s['quadrature']} | {s['passes']} | {s['dim']}D | "
                             f"P{s['degree']} | {', '.join(col['model'])} | {', '.join(col['solver'])} | "
                             f"{', '.join(col['friction'])} |")
    return "\n".join(lines) + "\n"


def cells_like(fixed: Mapping[str, Any]) -> Iterator[dict]:
    """Every cell with the axis values of ``fixed``."""
    free = [a for a in AXES if a not in fixed]
    for values in itertools.product(*(AXES[a] for a in free)):
        yield {**fixed, **dict(zip(free, values))}


if __name__ == "__main__":
    import sys

    sys.stdout.write(markdown())
