"""Speed against accuracy benchmark: every method over a sweep, error against wall time.

    python demos/bench.py --quick --main                # the main scenes, every method (make bench)
    python demos/bench.py --quick                       # every scene with a BENCH entry (make bench-all)
    python demos/bench.py --scene hertz --out results/bench

Writes <out>/<scene>.csv, .json, <scene>_pareto.png and <scene>_iterations.png
(see fenics_contact/app/bench.py).
"""
from fenics_contact.app.bench_run import main

main()
