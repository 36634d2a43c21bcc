"""The ``tube`` scene: a rubber tube crushed until its inner wall folds; the full tube's self-contact against the half
tube on its symmetry plane (the same problem by symmetry), on a coarse mesh."""
import numpy as np
import pytest
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.app import build
from fenics_contact.app.scenes import tube

COARSE = dict(n_theta=32, n_r=2, steps=16, fold_steps=8)
H = 2 * np.pi * tube.R_IN / COARSE["n_theta"]
K = tube.DEFAULT_K * tube.E / H


def solve(half: bool, comm=MPI.COMM_WORLD, **kw) -> tuple[list, list]:
    """The figures of every step and every step's record."""
    setup = build("tube", law=fc.make_law("penalty", K=K), half=half, comm=comm, **{**COARSE, **kw})
    solver = fc.Solver(setup.problem, quiet=True)
    figures = []
    for t in setup.loads:
        solver.run([t])
        figures.append(setup.figures())
    return figures, solver.records


def test_full_self_contact_equals_half_on_its_symmetry_plane():
    """At every step past first contact the full tube's plate force and fold force equal the half tube's to 1e-3 of
    the plate force; the fold closes and grows; its two sides overlap by no more than E / K; no cutback in either
    model."""
    full, full_records = solve(False)
    half, half_records = solve(True)
    assert len(full_records) == len(half_records) == len(full)  # every step at once: no cutback
    touched = [i for i, h in enumerate(half) if h["fold_force"] > 0]
    assert touched and touched[-1] == len(half) - 1
    for i in touched:
        f, h = full[i], half[i]
        for key in ("plate_force", "fold_force"):
            assert abs(f[key] - h[key]) <= 1e-3 * h["plate_force"], (i, key, f[key], h[key])
        assert f["fold_overlap"] <= tube.E / K, f
    widths = [full[i]["fold_width"] for i in touched]
    assert widths[-1] > widths[0] > 0 or widths[-1] > 0
    assert full[-1]["fold_force"] > 0.5 * full[-1]["plate_force"]


def test_parallel_equals_serial():
    """Under mpirun -n 2: every figure of every step of the full tube equals each rank's own serial run to 1e-8."""
    kw = dict(steps=8, fold_steps=4, approach=0.5)
    parallel, _ = solve(False, MPI.COMM_WORLD, **kw)
    serial, _ = solve(False, MPI.COMM_SELF, **kw)
    for a, b in zip(parallel, serial):
        for k in a:
            assert a[k] == pytest.approx(b[k], rel=1e-8, abs=1e-8 * max(abs(b["plate_force"]), 1.0)), (k, a[k], b[k])


def test_refusals():
    """Bad parameters: one line naming the parameter and its accepted range."""
    for kw, match in ((dict(approach=0.95), "approach must be in"), (dict(steps=0), "steps must be"),
                      (dict(fold_steps=1.5), "fold_steps must be"), (dict(n_theta=30), "multiple of 4"),
                      (dict(thickness=-1.0), "thickness must be")):
        with pytest.raises(ValueError, match=match):
            build("tube", law=fc.make_law("penalty", K=K), **kw)
    with pytest.raises(ValueError, match="method must be one of"):
        build("tube", law=fc.make_law("nitsche"))


def test_the_demos_check_fails_on_a_difference_or_an_overlap():
    """The demo's check (exit 3 when it fails): the worst difference of the two forces past first contact per the
    plate force against 1e-3, and the fold's overlap against E / K."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parent.parent / "fenics_contact" / "app" / "demos" / "tube.py"
    spec = importlib.util.spec_from_file_location("demo_tube", path)
    demo = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(demo)
    half = [{"approach": 1.0, "plate_force": 100.0, "fold_force": 0.0, "fold_overlap": -0.1},
            {"approach": 2.0, "plate_force": 200.0, "fold_force": 50.0, "fold_overlap": 1e-4}]
    same = [dict(h) for h in half]
    assert demo.agreement(same, half, 1e-3)["passed"]
    off = [dict(h) for h in half]
    off[1]["fold_force"] += 0.5  # 2.5e-3 of the plate force
    c = demo.agreement(off, half, 1e-3)
    assert not c["passed"] and c["rel_error"] == pytest.approx(2.5e-3)
    deep = [dict(h) for h in half]
    deep[1]["fold_overlap"] = 2e-3
    assert not demo.agreement(deep, half, 1e-3)["passed"]
    assert not demo.agreement(same[:1], half[:1], 1e-3)["passed"]  # the fold never closed
