"""Deprecated path of :mod:`fenics_contact.twobody.friction`, for one release.

Import from ``fenics_contact.twobody.friction`` (or ``fenics_contact``) instead; importing this module warns.
"""
import warnings

from .twobody.friction import FrictionalTwoBodySurface

__all__ = ["FrictionalTwoBodySurface"]

warnings.warn("fenics_contact.twobody_friction is deprecated: import from fenics_contact.twobody.friction",
              DeprecationWarning, stacklevel=2)
