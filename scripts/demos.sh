#!/usr/bin/env bash
# Run the demos under mpirun -n $NP and print one table of their checks (demos/table.py).
#   scripts/demos.sh quick [OUT]   every scene at a small size (make demo: under 3 minutes on 2 cores)
#   scripts/demos.sh all [OUT]     every demo with its default options (make demo-all)
# Exit status 1 if a demo failed or a check did not pass.
set -u
MODE=${1:-quick}
OUT=${2:-results}
PY=${PY:-.venv/bin/python}
NP=${NP:-2}
MPIRUN=${MPIRUN:-mpirun -n $NP}
if [ "$MODE" = quick ]; then
  RUNS=("block" "hertz" "slab --mu 0.4" "pin" "ring" "patch --main-only" "sphere --size 1.0"
        "compliance3d --mesh 8 4 2 --drag-steps 2" "seal" "cylinders --t-end 0.2 --h-contact 0.1"
        "sheet --n-arc 8 --eps 1e4 --steps 2" "rings --main-only --n 8")
elif [ "$MODE" = all ]; then
  RUNS=("block" "hertz" "slab" "pin" "ring" "patch" "sphere" "compliance3d" "seal" "cylinders" "sheet" "rings")
else
  echo "usage: $0 quick|all [OUT]" >&2; exit 2
fi
TIMER=(env)  # /usr/bin/time (Debian package time) when installed
[ -x /usr/bin/time ] && TIMER=(/usr/bin/time -f "   %e s wall, %U s user + %S s system (all ranks)")
failed=()
start=$(date +%s)
for run in "${RUNS[@]}"; do
  set -- $run
  demo=$1; shift
  rm -f "$OUT/$demo/summary.json"
  echo "== demos/$demo.py $* (mpirun -n $NP)"
  # wall and CPU seconds (all ranks): on a shared machine the CPU time / NP is the unloaded wall time
  if ! "${TIMER[@]}" $MPIRUN $PY demos/$demo.py --out "$OUT/$demo" --quiet "$@"; then
    failed+=("$demo")
  fi
done
echo "== all demos: $(( $(date +%s) - start )) s"
$PY demos/table.py "$OUT"
ok=$?
if [ ${#failed[@]} -gt 0 ]; then
  echo "failed: ${failed[*]}"
  exit 1
fi
exit $ok
