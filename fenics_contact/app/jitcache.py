"""FFCx's compiled forms loaded by file name. FFCx (0.5 to 0.11) finds the module of each form it loads with a new
``importlib`` FileFinder on its cache directory, which lists the whole directory each time: with every form ever
compiled on the machine there (tens of thousands of files) that is about 10 ms per form, and a benchmark sweep or a
test session loads thousands. :func:`find_modules_by_name` gives FFCx a finder that looks for the module's own
file names instead: the same module, found without listing the directory. The application's processes use it
(on import of :mod:`fenics_contact.app`); the library leaves FFCx as it is."""
from __future__ import annotations

import importlib.machinery
import importlib.util
import os
import types

__all__ = ["find_modules_by_name"]


class _ByName:
    """The part of ``importlib.machinery.FileFinder`` FFCx uses: ``find_spec`` of an extension module in ``path``."""

    def __init__(self, path: str, *loader_details):
        self.path = path

    def invalidate_caches(self) -> None:
        pass

    def find_spec(self, name: str, target=None):
        for suffix in importlib.machinery.EXTENSION_SUFFIXES:
            path = os.path.join(self.path, name + suffix)
            if os.path.exists(path):
                return importlib.util.spec_from_file_location(name, path)
        return None


def find_modules_by_name() -> bool:
    """Give FFCx's JIT the finder by file name; True if it was given (FFCx found, with the module layout of the
    releases 0.5 to 0.11), False otherwise (FFCx left alone)."""
    try:
        from ffcx.codegeneration import jit
    except ImportError:
        return False
    if isinstance(getattr(jit, "importlib", None), types.SimpleNamespace):
        return True  # given already
    if getattr(jit, "importlib", None) is not importlib or not hasattr(jit, "_load_objects"):
        return False  # another layout than 0.5 to 0.11
    machinery = types.SimpleNamespace(FileFinder=_ByName, ExtensionFileLoader=importlib.machinery.ExtensionFileLoader,
                                      EXTENSION_SUFFIXES=importlib.machinery.EXTENSION_SUFFIXES)
    jit.importlib = types.SimpleNamespace(machinery=machinery, util=importlib.util)
    return True
