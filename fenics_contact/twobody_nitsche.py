"""Deprecated path of :mod:`fenics_contact.twobody.nitsche`, for one release.

Import from ``fenics_contact.twobody.nitsche`` (or ``fenics_contact``) instead; importing this module warns.
"""
import warnings

from .twobody.nitsche import NitscheTwoBody

__all__ = ["NitscheTwoBody"]

warnings.warn("fenics_contact.twobody_nitsche is deprecated: import from fenics_contact.twobody.nitsche",
              DeprecationWarning, stacklevel=2)
