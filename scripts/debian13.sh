#!/usr/bin/env bash
# Second test lane: the suite on Debian 13's dolfinx (0.9) in a debootstrap root (scripts/lane_root.sh); the
# project is copied into a folder of it named after the checkout (no bind mount needed) and the tests run there
# serially and under mpirun -n 2.
# OPTIONAL=1 (used by `make test`): skip, saying why, when this machine cannot build the lane.
set -euo pipefail
cd "$(dirname "$0")/.."
LANE=debian13
. scripts/lane_root.sh
# Folder of the root the project is copied into: one per checkout, so that checkouts can share the root.
PROJECT=${DEB13_PROJECT:-project-$(pwd | md5sum | cut -c1-8)}
PY=${PY:-.venv/bin/python}
TESTS=${DEB13_TESTS:-tests}  # pytest arguments (a subset while developing)
MARK=${DEB13_MARK:-}  # a marker expression (make test: the parallel lane's), empty: every test

lane_root
if ! chroot "$DEB13" python3 -c "import dolfinx, gmsh, pytest, matplotlib, h5py" >/dev/null 2>&1; then
  lane_apt python3-dolfinx python3-gmsh python3-pytest python3-matplotlib python3-h5py openmpi-bin
fi
lane_copy "$PROJECT"

# Debian 13's Open MPI may hang here without these transport choices. With /proc and /sys mounted (lane_mounted)
# UCX reads the boot id and hwloc the CPU topology.
MPI_ENV=(OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,sm OMPI_MCA_pml=ob1
         OMPI_MCA_rmaps_base_oversubscribe=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1)
run() { lane_mounted "$1" "$PROJECT" "${MPI_ENV[@]}" PYTHONPATH=/$PROJECT; }
echo "debian13 lane: dolfinx $(run "python3 -c 'import dolfinx; print(dolfinx.__version__)'")"
start=$(date +%s)
# SERIAL=0 (used by `make test`, to stay within its time): only the mpirun -n 2 run; the serial code paths
# are tested by the Debian 12 lane, and the figures below are computed serially on both.
if [ "${SERIAL:-1}" = 1 ]; then
  run "python3 -m pytest -q -p no:cacheprovider ${MARK:+-m '$MARK'} $TESTS"
fi
# A test that does not end, or ends on one rank only, ends the run with its name (tests/conftest.py).
run "mpirun -n 2 python3 -m pytest -q -p no:cacheprovider ${MARK:+-m '$MARK'} $TESTS"
# Same figures on both dolfinx versions: block and hertz, 1e-8 relative.
"$PY" scripts/lane_figures.py "$DEB13/$PROJECT/figures-debian12.json"
run "python3 scripts/lane_figures.py figures-debian13.json"
"$PY" scripts/lane_figures.py --compare "$DEB13/$PROJECT/figures-debian12.json" \
  "$DEB13/$PROJECT/figures-debian13.json"
echo "debian13 lane: passed in $(( $(date +%s) - start )) s"
