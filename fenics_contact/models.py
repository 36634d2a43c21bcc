"""The bulk models by name (:data:`MODELS`): the capability grid's ``model`` axis, the demos' ``--model``; and
the warning a displacement-only model gets where it locks (:func:`locking_warning`)."""
from __future__ import annotations

from .incompressible import MixedLinearElastic, MixedNeoHookean
from .materials import LinearElastic, NeoHookean

__all__ = ["MODELS", "MIXED_MODELS", "LOCKING_NU", "locking_warning"]

MODELS = {"linear": LinearElastic, "neohookean": NeoHookean, "neohookean-mixed": MixedNeoHookean,
          "linear-mixed": MixedLinearElastic}
MIXED_MODELS = tuple(name for name, model in MODELS.items() if model.mixed)

# Poisson's ratio from which a displacement-only element locks: lambda / mu = 2 nu / (1 - 2 nu) = 49 at 0.49, and
# the volumetric energy's constraint div u ~ 0 stiffens the element (a sphere into P1 rubber at nu = 0.4999: +42 %
# force, the peak pressure +90-170 %; the mixed models within 1 % of Hertz).
LOCKING_NU = 0.49


def locking_warning(material, degree: int) -> str | None:
    """The warning of a displacement-only ``material`` (a :class:`~fenics_contact.materials.Material` or
    :class:`~fenics_contact.materials.Materials`) on Lagrange elements of ``degree`` at ``nu >=``
    :data:`LOCKING_NU` (volumetric locking: too stiff, forces and pressures too high), naming the mixed models;
    None for a mixed model or a smaller ``nu``."""
    bodies = list(material.by_tag.values()) if hasattr(material, "by_tag") else [material]
    nu = max((m.nu for m in bodies if not m.mixed), default=None)
    if nu is None or nu < LOCKING_NU:
        return None
    return (f"volumetric locking: a displacement-only model on P{degree} elements at nu = {nu:g} >= {LOCKING_NU:g} "
            f"is too stiff (forces and pressures too high, a finite-strain neohookean as much as linear); use a "
            f"mixed displacement-pressure model: {', '.join(MIXED_MODELS)} (fc.MixedNeoHookean, "
            f"fc.MixedLinearElastic on the unknown of fc.unknown(mesh, 2, law, model=...))")
