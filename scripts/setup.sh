#!/usr/bin/env bash
# One-time set-up on Debian 12 (idempotent): system packages, then the venv.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-.venv}
APT_PACKAGES="python3-dolfinx python3-gmsh python3-h5py python3-venv openmpi-bin"

if ! /usr/bin/python3 -c "import dolfinx, gmsh, h5py" 2>/dev/null || ! command -v mpirun >/dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "setup: installing $APT_PACKAGES (apt)"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q $APT_PACKAGES
fi

STAMP="$VENV/.fenics_contact-installed"
if [ ! -f "$STAMP" ] || [ pyproject.toml -nt "$STAMP" ] || [ scripts/constraints.txt -nt "$STAMP" ]; then
  echo "setup: creating $VENV (system site packages, numpy<2)"
  /usr/bin/python3 -m venv --system-site-packages "$VENV"
  # The project's requirements and extras but gmsh and h5py: Debian's carry no pip metadata (gmsh.py alone; h5py
  # as h5py._debian_h5py_serial), so pip would put PyPI's over them. numpy 2 would break the system petsc4py at
  # import: scripts/constraints.txt keeps it below 2 in every install.
  REQS=$("$VENV/bin/python" -c '
import re, tomllib
project = tomllib.load(open("pyproject.toml", "rb"))["project"]
reqs = project["dependencies"] + [r for e in ("tests", "demos", "docs") for r in project["optional-dependencies"][e]]
print(" ".join(r for r in reqs if re.split(r"[<>=!~;\[ ]", r)[0] not in ("gmsh", "h5py")))')
  "$VENV/bin/pip" install -q --disable-pip-version-check --no-warn-conflicts -c scripts/constraints.txt --no-deps -e .
  "$VENV/bin/pip" install -q --disable-pip-version-check --no-warn-conflicts -c scripts/constraints.txt $REQS
  touch "$STAMP"
fi
