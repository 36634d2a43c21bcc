"""The compiler's commands of a form's first JIT kept out of the root log: setuptools (distutils, run by cffi
when FFCx compiles a form) logs every command to the root logger at INFO (``INFO:root:running build_ext`` ...),
a flood in any script that logs at INFO. A filter on the root logger drops those records alone (below WARNING,
logged from distutils' own modules); the user's records to the root logger pass."""
from __future__ import annotations

import logging
import os

__all__ = ["quiet_compiler"]

_DISTUTILS = (f"{os.sep}distutils{os.sep}", f"{os.sep}_distutils{os.sep}")


def _not_a_compiler_command(record: logging.LogRecord) -> bool:
    return record.levelno >= logging.WARNING or not any(part in record.pathname for part in _DISTUTILS)


def quiet_compiler() -> None:
    """Install the filter on the root logger (once; :mod:`fenics_contact` does on import)."""
    root = logging.getLogger()
    if not any(getattr(f, "_fenics_contact_jit", False) for f in root.filters):
        quiet = logging.Filter()
        quiet.filter = _not_a_compiler_command
        quiet._fenics_contact_jit = True
        root.addFilter(quiet)
