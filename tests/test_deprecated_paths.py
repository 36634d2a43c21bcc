"""The two-body enforcements' old top-level import paths: they still work for one release, and they warn."""
import importlib
import subprocess
import sys
import warnings

import pytest
from mpi4py import MPI


@pytest.mark.parametrize("old, new, name", [
    ("fenics_contact.twobody_friction", "fenics_contact.twobody.friction", "FrictionalTwoBodySurface"),
    ("fenics_contact.twobody_nitsche", "fenics_contact.twobody.nitsche", "NitscheTwoBody"),
    ("fenics_contact.twobody_nitsche_friction", "fenics_contact.twobody.nitsche_friction", "NitscheFrictionTwoBody"),
])
def test_old_path_reexports_with_a_warning(old, new, name):
    sys.modules.pop(old, None)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = importlib.import_module(old)
    assert getattr(module, name) is getattr(importlib.import_module(new), name)
    assert any(issubclass(w.category, DeprecationWarning) and new in str(w.message) for w in caught)


@pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="a subprocess from the serial lane only")
def test_package_does_not_use_old_paths():
    """The library and the application import the new paths only: no DeprecationWarning on importing them all."""
    code = ("import pkgutil, importlib, fenics_contact, fenics_contact.app.scenes as s\n"
            "[importlib.import_module(m.name) for m in pkgutil.iter_modules(s.__path__, s.__name__ + '.')]\n"
            "import fenics_contact.methods.builders, fenics_contact.mortar.nitsche_surface")
    subprocess.run([sys.executable, "-W", "error::DeprecationWarning", "-c", code], check=True)
