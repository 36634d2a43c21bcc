"""The ``lipseal`` scene: a U-cup squeezed until its lips close the slot between them; the full seal's self-contact
against the half seal on its symmetry plane (the same problem by symmetry), on a coarse mesh."""
import numpy as np
import pytest
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.app import build
from fenics_contact.app.scenes import lipseal

COARSE = dict(nx=6, ny_heel=4, ny_lip=12, steps=20)
H = np.hypot(lipseal.LIP, 0.5 * lipseal.SLOT) / COARSE["ny_lip"]
K = lipseal.DEFAULT_K * lipseal.E / H


def solve(half: bool, comm=MPI.COMM_WORLD, **kw) -> tuple[list, list]:
    """The figures of every step and every step's record."""
    setup = build("lipseal", law=fc.make_law("penalty", K=K), half=half, comm=comm, **{**COARSE, **kw})
    solver = fc.Solver(setup.problem, quiet=True)
    figures = []
    for t in setup.loads:
        solver.run([t])
        figures.append(setup.figures())
    return figures, solver.records


def test_full_self_contact_equals_half_on_its_symmetry_plane():
    """At every step past first contact the full seal's plate force and slot force equal the half seal's to 1e-3 of
    the plate force; the slot closes and its closed length grows to nearly the whole lip; the lips overlap by no more
    than E / K; no cutback in either model; at the end the closed slot carries the rod's force (the lips pressed
    on each other: self-contact is what holds the seal)."""
    full, full_records = solve(False)
    half, half_records = solve(True)
    assert len(full_records) == len(half_records) == len(full)  # every step at once: no cutback
    touched = [i for i, h in enumerate(half) if h["slot_force"] > 0]
    assert touched and touched[-1] == len(half) - 1 and touched[0] > 0  # open at first, closed to the end
    for i in touched:
        f, h = full[i], half[i]
        for key in ("plate_force", "slot_force"):
            assert abs(f[key] - h[key]) <= 1e-3 * h["plate_force"], (i, key, f[key], h[key])
        assert f["slot_overlap"] <= lipseal.E / K, f
    widths = [full[i]["slot_width"] for i in touched if full[i]["slot_width"] > 0]
    assert widths == sorted(widths) and widths[-1] > 0.9 * lipseal.LIP
    assert full[-1]["slot_force"] > 0.9 * full[-1]["plate_force"]


def test_parallel_equals_serial():
    """Under mpirun -n 2: every figure of every step of the full seal equals each rank's own serial run to 1e-8."""
    kw = dict(steps=10, ny_lip=8, nx=4, ny_heel=2, squeeze=0.16)
    parallel, _ = solve(False, MPI.COMM_WORLD, **kw)
    serial, _ = solve(False, MPI.COMM_SELF, **kw)
    assert parallel[-1]["slot_force"] > 0
    for a, b in zip(parallel, serial):
        for k in a:
            assert a[k] == pytest.approx(b[k], rel=1e-8, abs=1e-8 * max(abs(b["plate_force"]), 1.0)), (k, a[k], b[k])


def test_refusals():
    """Bad parameters: one line naming the parameter and its accepted range."""
    for kw, match in ((dict(squeeze=0.5), "squeeze must be in"), (dict(steps=0), "steps must be"),
                      (dict(nx=0), "nx must be"), (dict(slot=-1.0), "slot must be"),
                      (dict(flare=-0.1), "flare must be"), (dict(slot=6.0), "slot must be narrower")):
        with pytest.raises(ValueError, match=match):
            build("lipseal", law=fc.make_law("penalty", K=K), **kw)
    with pytest.raises(ValueError, match="method must be one of"):
        build("lipseal", law=fc.make_law("nitsche"))


def test_the_demos_check_fails_on_a_difference_or_an_overlap():
    """The demo's check (exit 3 when it fails): the worst difference of the two forces past first contact per the
    plate force against 1e-3, and the lips' overlap against E / K."""
    from fenics_contact.app.demos import lipseal as demo

    half = [{"squeeze": 0.1, "plate_force": 10.0, "slot_force": 0.0, "slot_overlap": -0.1},
            {"squeeze": 0.2, "plate_force": 200.0, "slot_force": 190.0, "slot_overlap": 1e-4}]
    same = [dict(h) for h in half]
    assert demo.agreement(same, half, 1e-3)["passed"]
    off = [dict(h) for h in half]
    off[1]["slot_force"] += 0.5  # 2.5e-3 of the plate force
    c = demo.agreement(off, half, 1e-3)
    assert not c["passed"] and c["rel_error"] == pytest.approx(2.5e-3)
    deep = [dict(h) for h in half]
    deep[1]["slot_overlap"] = 2e-3
    assert not demo.agreement(deep, half, 1e-3)["passed"]
    assert not demo.agreement(same[:1], half[:1], 1e-3)["passed"]  # the slot never closed
