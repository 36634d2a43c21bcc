"""Exact Signorini-Coulomb contact on the stiffness condensed onto the contact dofs (method ``coulomb``).

Formulation 1.6 (Renaud & Feng 2003), for linear elasticity, small displacements, nodal (vertex) contact, in
2D or 3D, against a flat rigid obstacle or between two deformable bodies in small sliding. The stiffness is
condensed onto the contact dofs (a Schur complement, :mod:`.operator`); each load step, Alart-Curnier's
semismooth Newton solves the contact conditions on the contact dofs alone (:mod:`.newton`; the Coulomb disk of
:mod:`.disk`, an interval in 2D), and the displacement is recovered by one solve. No penalty: the contact
conditions hold exactly.

- :class:`CondensedContact` (:mod:`.rigid_surface`) and its step solver :class:`CondensedCoulomb`
  (:mod:`.rigid_solver`): a half-plane with an axis-aligned normal.
- :class:`CondensedTwoBody` (:mod:`.two_body_surface`) and its step solver :class:`CondensedTwoBodyCoulomb`
  (:mod:`.two_body_solver`): two bodies, slave vertices paired once with the master facets.
- :func:`step_solver_for`: the step solver a list of contact surfaces needs (give it to the problem).

Sign convention: gap > 0 penetration (the distance ``d = -gap`` >= 0 open), pressure > 0 compression.
"""
from __future__ import annotations

from .rigid_solver import CondensedCoulomb
from .rigid_surface import CondensedContact
from .states import OPEN, P_TOL, SLIP, STICK, T_TOL, StepFailure, classify
from .step import CondensedStepSolver
from .two_body_solver import CondensedTwoBodyCoulomb
from .two_body_surface import CondensedTwoBody

__all__ = [
    "OPEN", "SLIP", "STICK", "P_TOL", "T_TOL", "classify", "StepFailure", "CondensedContact",
    "CondensedCoulomb", "CondensedTwoBody", "CondensedTwoBodyCoulomb", "CondensedStepSolver", "step_solver_for"
]


def step_solver_for(contacts) -> CondensedStepSolver | None:
    """The step solver ``contacts`` need: a :class:`CondensedCoulomb` (rigid obstacle) or a
    :class:`CondensedTwoBodyCoulomb` (two bodies) for the one that requires it (method ``coulomb``), or None when
    none does.

    Raises:
        ValueError: more than one surface requires a step solver (one condensed surface per problem).

    Args:
        contacts: the problem's contact surfaces.

    Returns:
        The step solver for :class:`ContactProblem`'s ``step_solver``, or None.
    """
    need = [c for c in contacts if c.requires_step_solver]
    if len(need) > 1:
        raise ValueError(f"method 'coulomb' condenses one contact surface, got {len(need)}: "
                         f"{', '.join(c.name for c in need)}")
    if not need:
        return None
    return CondensedTwoBodyCoulomb(need[0]) if isinstance(need[0], CondensedTwoBody) else CondensedCoulomb(need[0])
