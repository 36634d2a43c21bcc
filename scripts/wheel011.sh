#!/usr/bin/env bash
# Third test lane: the suite on dolfinx 0.11 from the PyPI wheel dolfinx-solver-real (dolfinx, PETSc with MUMPS and
# MPICH in one wheel; Python >= 3.12), as a user installs it: a venv of the Debian 13 root's Python 3.13
# (scripts/lane_root.sh) without the system site packages (the root's apt dolfinx 0.9 stays out), the wheel, then
# `pip install <copy of the checkout>[tests]`. MPI runs use the wheel's own mpiexec (MPICH), which needs /proc and
# /sys: mounted for each command in a private mount namespace, gone when it ends.
#   WHEEL_PARTS   what to run, any of: setup (nothing but the set-up), tests (the tests, serially), mpi (the same
#                 under mpiexec -n 2), tutorials (serially and under mpiexec -n 2), demos (the quick set under
#                 mpiexec -n 2), figures (the lane figures against Debian 12's, serially and under mpiexec -n 2);
#                 default: all
#   WHEEL_TESTS   the test files (default: tests/test_*.py)
#   WHEEL_MARK    a marker expression (make test-wheel: the parallel lane's; empty: every test)
# OPTIONAL=1 (used by `make test`): skip, saying why, when this machine cannot build the lane.
set -euo pipefail
cd "$(dirname "$0")/.."
LANE=wheel011
. scripts/lane_root.sh
WHEEL=${WHEEL:-dolfinx-solver-real==0.11.0.post0}
VENV=/opt/fc-wheel  # in the root
PROJECT=${WHEEL_PROJECT:-wheel-$(pwd | md5sum | cut -c1-8)}
PY=${PY:-.venv/bin/python}
PARTS=${WHEEL_PARTS:-tests mpi tutorials demos figures}
TESTS=${WHEEL_TESTS:-$(echo tests/test_*.py)}
MARK=${WHEEL_MARK:-}  # empty: every test
MPIEXEC="$VENV/bin/mpiexec -n 2"

command -v unshare >/dev/null || skip "no unshare (util-linux) for the mounts MPICH needs"
lane_root
# python3-venv: the venv; gcc, python3-dev: FFCx compiles the forms; the rest: the gmsh wheel's libraries.
lane_apt python3-venv gcc python3-dev libgl1 libglu1-mesa libxcursor1 libxinerama1 libxft2 libgomp1 \
  || skip "apt-get install in $DEB13 failed"
# pip in the root checks the index's certificate against the host's authorities (a proxy's may be among them).
cp /etc/ssl/certs/ca-certificates.crt "$DEB13/etc/ssl/host-ca-certificates.crt"
PIP_ENV=(PIP_CERT=/etc/ssl/host-ca-certificates.crt PIP_DISABLE_PIP_VERSION_CHECK=1)
# Every command: the venv first on PATH, one BLAS/OpenMP thread per rank.
ENV=(PATH=$VENV/bin:/usr/bin:/bin OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 MPLBACKEND=Agg)
run() { lane_mounted "$1" "$PROJECT" "${ENV[@]}" "${PIP_ENV[@]}"; }

pkg=${WHEEL%%[=<>]*}
installed=$(lane_mounted "pip show $pkg 2>/dev/null | sed -n 's/^Version: //p'" / "${ENV[@]}" 2>/dev/null || true)
if [ "$installed" != "${WHEEL##*==}" ] || ! lane_mounted "python -c 'import dolfinx'" / "${ENV[@]}" 2>/dev/null; then
  echo "wheel011 lane: python3 -m venv $VENV; pip install $WHEEL"
  rm -rf "${DEB13:?}$VENV"
  chroot "$DEB13" python3 -m venv "$VENV"
  lane_mounted "pip install -q '$WHEEL'" / "${ENV[@]}" "${PIP_ENV[@]}" || skip "pip install $WHEEL failed"
  # The wheel's MPI must be loaded before dolfinx: its package does it when imported first.
  echo "import dolfinx_solver" > "$DEB13$VENV/lib/$(chroot "$DEB13" python3 -c \
    'import sys; print(f"python{sys.version_info[0]}.{sys.version_info[1]}")')/site-packages/00-dolfinx-solver.pth"
fi
lane_copy "$PROJECT"
run "pip install -q '.[tests]'"
echo "wheel011 lane: dolfinx $(run "python -c 'import dolfinx; print(dolfinx.__version__)'"), $WHEEL"

# One pytest process per test file ($1: the launcher, empty or mpiexec): MPICH gives a process 2048 communicators,
# fewer than the meshes of a whole session hold (each test's are held to its end, with the PETSc objects the
# test dropped; Open MPI has no such cap).
run_tests() {
  local failed=() f rc
  for f in $TESTS; do
    rc=0
    run "$1 python -m pytest -q -p no:cacheprovider ${MARK:+-m '$MARK'} $f" || rc=$?
    [ $rc -eq 0 ] || [ $rc -eq 5 ] || failed+=("$f")  # 5: no test of the file selected
  done
  [ ${#failed[@]} -eq 0 ] || { echo "wheel011 lane: failed: ${failed[*]}" >&2; return 1; }
}

start=$(date +%s)
for part in $PARTS; do
  case $part in
    tests) run_tests "" ;;
    mpi) run_tests "$MPIEXEC" ;;
    tutorials)
      # From a folder without the checkout's package: the tutorials import the installed copy.
      for t in tutorials/[0-9]*.py; do
        for mpi in "" "$MPIEXEC"; do
          out=$(run "cd /tmp && $mpi python /$PROJECT/$t" 2>&1) \
            || { echo "$out"; echo "wheel011 lane: $t ${mpi:+($mpi) }failed" >&2; exit 1; }
          echo "$t${mpi:+ ($mpi)}: ${out##*$'\n'}"
        done
      done ;;
    demos) run "PY=python MPIRUN='$MPIEXEC' bash scripts/demos.sh quick results/wheel011" ;;
    figures)
      # The same figures as on Debian 12 (and so as on Debian 13's 0.9), 1e-8 relative: serially and on 2 ranks.
      "$PY" scripts/lane_figures.py "$DEB13/$PROJECT/figures-debian12.json"
      run "python scripts/lane_figures.py figures-wheel011.json && $MPIEXEC python scripts/lane_figures.py \
        figures-wheel011-np2.json"
      for f in figures-wheel011.json figures-wheel011-np2.json; do
        "$PY" scripts/lane_figures.py --compare "$DEB13/$PROJECT/figures-debian12.json" "$DEB13/$PROJECT/$f"
      done ;;
    setup) ;;
    *) echo "wheel011 lane: unknown part '$part' of WHEEL_PARTS (setup tests mpi tutorials demos figures)" >&2
       exit 2 ;;
  esac
done
echo "wheel011 lane: $PARTS passed in $(( $(date +%s) - start )) s"
