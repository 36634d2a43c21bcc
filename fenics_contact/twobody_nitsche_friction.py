"""Deprecated path of :mod:`fenics_contact.twobody.nitsche_friction`, for one release.

Import from ``fenics_contact.twobody.nitsche_friction`` (or ``fenics_contact``) instead; importing this module warns.
"""
import warnings

from .twobody.nitsche_friction import NitscheFrictionTwoBody

__all__ = ["NitscheFrictionTwoBody"]

warnings.warn("fenics_contact.twobody_nitsche_friction is deprecated: import from "
              "fenics_contact.twobody.nitsche_friction", DeprecationWarning, stacklevel=2)
