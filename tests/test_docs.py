"""The HTML documentation builds, Sphinx warnings as errors: the pages of docs/ (MyST markdown) and the API
reference from the docstrings (``make docs`` without regenerating the generated pages). Slow lane, serial only;
skipped where the ``docs`` extra is not installed (the Debian 13 lane runs the distribution's Python)."""
import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest
from mpi4py import MPI

ROOT = Path(__file__).resolve().parent.parent
serial = pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="a subprocess from the serial lane only")
MISSING = [m for m in ("sphinx", "myst_parser") if importlib.util.find_spec(m) is None]


@serial
@pytest.mark.skipif(bool(MISSING), reason=f"{' and '.join(MISSING)} not importable: the docs extra "
                                          "(pip install -e '.[docs]') is not installed")
def test_html_documentation_builds_without_warnings(tmp_path):
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_"))}
    out = tmp_path / "html"
    proc = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                           str(ROOT / "docs"), str(out)], capture_output=True, text=True, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert not proc.stderr.strip(), proc.stderr
    api = (out / "api.html").read_text()
    for anchor in ("fenics_contact.Solver", "fenics_contact.contact_surface", "module-fenics_contact.capabilities"):
        assert f'id="{anchor}"' in api, anchor  # autodoc imported the package and documented it
