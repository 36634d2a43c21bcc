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
if [ ! -f "$STAMP" ] || [ pyproject.toml -nt "$STAMP" ]; then
  echo "setup: creating $VENV (system site packages, numpy<2)"
  /usr/bin/python3 -m venv --system-site-packages "$VENV"
  # numpy 2 would break the system petsc4py at import: keep it below 2 in every install.
  "$VENV/bin/pip" install -q --disable-pip-version-check "numpy<2" -e ".[tests,demos,docs]" -c scripts/constraints.txt
  touch "$STAMP"
fi
