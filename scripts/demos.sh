#!/usr/bin/env bash
# Run the demos under mpirun -n $NP and print one table of their checks (demos/table.py).
#   scripts/demos.sh quick [OUT]   the lines of demos/quick.txt: every demo at a small size (make demo)
#   scripts/demos.sh all [OUT]     every demo with its default options (make demo-all)
# Exit status 1 if a demo failed or a check did not pass.
set -u
MODE=${1:-quick}
OUT=${2:-results}
PY=${PY:-.venv/bin/python}
NP=${NP:-2}
MPIRUN=${MPIRUN:-mpirun -n $NP}
DRIVERS="bench scaling table"  # demos/*.py that are not demos
if [ "$MODE" = quick ]; then
  mapfile -t RUNS < <(grep -v '^#' demos/quick.txt | grep -v '^ *$')  # one list, shared with the smoke test
elif [ "$MODE" = all ]; then
  RUNS=()
  for f in demos/*.py; do
    name=$(basename "$f" .py)
    case " $DRIVERS " in *" $name "*) ;; _*) ;; *) RUNS+=("$name") ;; esac
  done
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
