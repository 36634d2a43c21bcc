# make demo: set up (apt packages, venv), run every scene's demo at a small size under mpirun -n 2 into results/
#            and print one table of their checks (figure, reference, error, passed); make demo-all: default sizes
# make test: set up and run ruff, every test but the studies serially (two at a time), and under mpirun -n 2 (on
#            dolfinx 0.5 and on Debian 13's 0.9) the library's unit and closed-form tests and every comparison of
#            ranks; on the dolfinx 0.11 wheel the tutorials and the lane figures; within 20 minutes on 2 cores
# make test-fast: the library's unit and closed-form tests (not slow, no scene), under 2 minutes
# make test-all: every test serially, under mpirun -n 2 and on Debian 13 (serial and mpirun -n 2), and the whole
#            dolfinx 0.11 wheel lane (make test-wheel)
# make bench: the quick benchmark sweep (the main scenes, every method, within 10 minutes on 2 cores) into
#             results/bench and its pages into docs/bench/ (make bench-pages); make bench-all: every scene with its
#             stability map, locking and model reduction into results/bench-all, then every page (docs/benchmarks.md)
# make docs: regenerate the generated pages (also docs/tutorials/ from tutorials/), build the HTML documentation into docs/_build/html (warnings are errors)
# Lanes: the markers slow, scene, mpi and study, given in tests/conftest.py
VENV   ?= .venv
PY     := $(VENV)/bin/python
NP     ?= 2
export OMPI_ALLOW_RUN_AS_ROOT=1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
# one BLAS/OpenMP thread per rank: on 2 cores, threads x ranks oversubscribe and crawl
export OPENBLAS_NUM_THREADS=1
export OMP_NUM_THREADS=1
# each process's address space is capped (KiB): a run that grows is stopped with a MemoryError, not by the kernel
MEM_CAP_KB ?= 4000000
# make test-mpi-all: one process per rank runs every test, each rank holding a whole LU factorization (the
# repeatable LU, docs/guide/parallel.md), the 3D studies' included
MEM_CAP_ALL_KB ?= 6000000
MPIRUN := mpirun -n $(NP)

PYTEST := $(PY) -m pytest -q -p no:cacheprovider
XDIST  := -n $(NP) --dist loadfile
# in parallel (and on Debian 13), make test runs the library's unit and closed-form tests and every comparison
# of ranks; the demos run under mpirun -n 2 in make demo, every test in parallel in make test-all
PARALLEL_LANE := (not slow and not scene) or mpi

.PHONY: setup demo demo-all bench bench-all bench-pages scaling friction-scaling docs test test-fast test-all lint test-serial test-serial-all test-mpi \
        test-mpi-all \
        test-debian13 test-wheel clean peer felupe

setup:
	@VENV=$(VENV) bash scripts/setup.sh

demo: setup
	@PY=$(PY) NP=$(NP) bash scripts/demos.sh quick results

demo-all: setup
	@PY=$(PY) NP=$(NP) bash scripts/demos.sh all results/all

# speed against accuracy, every method on the same scene: the main scenes (make bench; the pages of the other
# scenes are kept) or every scene with a BENCH entry and its maps (make bench-all; every page rewritten), then the
# pages in docs/bench/ (make bench-pages: the pages alone, from BENCH_OUT; make docs does not need them). The pages
# are written even when a scene failed (one line each); the sweep's exit status is kept.
BENCH_OUT ?= results/bench
BENCH_PAGES_ARGS ?= --add
bench: setup
	@status=0; $(PY) demos/bench.py --quick --main --out results/bench || status=$$?; \
	$(MAKE) --no-print-directory bench-pages BENCH_OUT=results/bench BENCH_PAGES_ARGS=--add || status=1; \
	exit $$status

bench-all: setup
	@status=0; $(PY) demos/bench.py --quick --out results/bench-all || status=$$?; \
	$(MAKE) --no-print-directory bench-pages BENCH_OUT=results/bench-all BENCH_PAGES_ARGS= || status=1; \
	exit $$status

bench-pages: setup
	$(PY) -m fenics_contact.app.bench_pages $(BENCH_OUT) docs/bench $(BENCH_PAGES_ARGS) \
		$(if $(wildcard results/*/summary.json),--demos results)

# 3D Hertz (sphere on a rigid plane, on a deformable block) from ~1e4 to ~1e6 dofs, serial and mpirun -n 2:
# peak memory, time per Newton iteration, slope, speed-up -> results/scaling/scaling.json (heavy: see docs/benchmarks.md)
SCALING_ARGS ?=
scaling: setup
	$(PY) demos/scaling.py --out results/scaling $(SCALING_ARGS)

# Cattaneo-Mindlin's sphere (mindlin3d) refined: the sparse exact method beside penalty and Nitsche friction, GMRES +
# GAMG, mpirun -n 2 -> results/friction_scaling/friction_scaling.json (heavy: see docs/benchmarks.md)
FRICTION_SCALING_ARGS ?=
friction-scaling: setup
	$(PY) demos/friction_scaling.py --out results/friction_scaling $(FRICTION_SCALING_ARGS)

# the peer side by side: dolfinx_contact (installed in the Debian 13 root under PEER_PREFIX, default /opt/peer; its
# demos from the checkout PEER_SRC) and this suite on the same four cases, one run -> docs/bench/peer.md (needs root;
# not part of make test; see docs/benchmarks.md)
PEER_SRC ?=
PEER_PREFIX ?= /opt/peer
PEER_ARGS ?=
peer: setup
	@test -n "$(PEER_SRC)" || { echo "make peer: give PEER_SRC=/path/to/asimov-contact (its source checkout)" >&2; exit 2; }
	$(PY) scripts/peer/run.py --peer-src "$(PEER_SRC)" --peer-prefix "$(PEER_PREFIX)" $(PEER_ARGS)

# FElupe side by side: FElupe (from the package index, in its own venv under ~/.cache/fenics_contact, made if
# missing) and this suite on the O-ring cord between two plates, plane strain and axisymmetric, one run ->
# docs/bench/felupe.md (not part of make test; see docs/benchmarks.md)
FELUPE_ARGS ?=
felupe: setup
	$(PY) scripts/felupe/run.py $(FELUPE_ARGS)

# the generated pages (capability matrix, methods, layout; tests check the committed files), then the HTML
# documentation with the API reference in docs/_build/html (warnings are errors)
docs: setup
	$(PY) -m fenics_contact.capabilities > docs/capabilities.md
	$(PY) -m fenics_contact.methods > docs/methods.md
	$(PY) scripts/layout.py > docs/layout.md
	$(PY) scripts/tutorials.py
	$(VENV)/bin/sphinx-build -W --keep-going -b html docs docs/_build/html

lint: setup
	$(VENV)/bin/ruff check fenics_contact tests scripts tutorials

test-fast: setup
	ulimit -v $(MEM_CAP_KB) && $(PYTEST) $(XDIST) -m "not slow and not scene" tests

test-serial: setup
	ulimit -v $(MEM_CAP_KB) && $(PYTEST) $(XDIST) -m "not study" tests

test-serial-all: setup
	ulimit -v $(MEM_CAP_KB) && $(PYTEST) $(XDIST) tests

test-mpi: setup
	ulimit -v $(MEM_CAP_KB) && $(MPIRUN) $(PYTEST) -m "$(PARALLEL_LANE)" tests

test-mpi-all: setup
	ulimit -v $(MEM_CAP_ALL_KB) && $(MPIRUN) $(PYTEST) tests

# Debian 13 (dolfinx 0.9) lane in a debootstrap root; `make test` skips it, saying so, where it cannot run.
test-debian13: setup
	bash scripts/debian13.sh

# dolfinx 0.11 lane: the PyPI wheel dolfinx-solver-real in a venv of the Debian 13 root, the project pip-installed
# into it; the library's and the parallel lane's tests serially and under the wheel's mpiexec -n 2, the tutorials,
# the quick demos and the lane figures (WHEEL_PARTS picks some). `make test` runs the tutorials and the figures.
test-wheel: setup
	WHEEL_MARK="$(PARALLEL_LANE)" bash scripts/wheel011.sh

test: lint test-serial test-mpi
	@OPTIONAL=1 SERIAL=0 DEB13_MARK="$(PARALLEL_LANE)" bash scripts/debian13.sh
	@OPTIONAL=1 WHEEL_PARTS="tutorials figures" bash scripts/wheel011.sh

test-all: lint test-serial-all test-mpi-all test-debian13 test-wheel

clean:
	rm -rf results .pytest_cache docs/_build
