#!/usr/bin/env bash
# Run the demos under mpirun -n $NP and print one table of their checks (demos/table.py).
#   scripts/demos.sh quick [OUT]   the lines of demos/quick.txt (or of $QUICK): every demo at a small size (make demo)
#   scripts/demos.sh all [OUT]     every demo with its default options (make demo-all)
# Exit status 1 if a demo failed (an error) or its check did not pass (the demo's exit status 3); both are named.
set -u
MODE=${1:-quick}
OUT=${2:-results}
PY=${PY:-.venv/bin/python}
NP=${NP:-2}
MPIRUN=${MPIRUN:-mpirun -n $NP}
DRIVERS="bench scaling table"  # demos/*.py that are not demos
if [ "$MODE" = quick ]; then
  mapfile -t RUNS < <(grep -v '^#' "${QUICK:-demos/quick.txt}" | grep -v '^ *$')  # one list, shared with the smoke test
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
failed=()    # demos that ended in an error
unchecked=() # demos that ran but whose check failed (exit status 3, fenics_contact.app.cli.EXIT_CHECK)
start=$(date +%s)
for run in "${RUNS[@]}"; do
  set -- $run
  demo=$1; shift
  echo "== demos/$demo.py $* (mpirun -n $NP)"
  # wall and CPU seconds (all ranks): on a shared machine the CPU time / NP is the unloaded wall time
  "${TIMER[@]}" $MPIRUN $PY demos/$demo.py --out "$OUT/$demo" --overwrite --quiet "$@"
  status=$?
  if [ $status -eq 3 ]; then
    unchecked+=("$demo")
  elif [ $status -ne 0 ]; then
    failed+=("$demo (exit status $status)")
  fi
done
echo "== all demos: $(( $(date +%s) - start )) s"
$PY demos/table.py "$OUT"
ok=$?
[ ${#unchecked[@]} -gt 0 ] && echo "demos whose check failed (exit status 3): ${unchecked[*]}"
[ ${#failed[@]} -gt 0 ] && echo "demos that failed: ${failed[*]}"
if [ ${#failed[@]} -gt 0 ] || [ ${#unchecked[@]} -gt 0 ]; then
  exit 1
fi
exit $ok
