"""Model reduction on hertz: the quarter disk and the half disk solve the same problem."""
import numpy as np

from fenics_contact.app.scenes import hertz
from fenics_contact.methods import make_law
from fenics_contact.solver import Solver


def figures(symmetry):
    setup = hertz.build(make_law("auglag", K=hertz.DEFAULT_K), symmetry=symmetry, steps=1)
    solver = Solver(setup.problem, augment_max=30, augment_tol=1e-10, quiet=True)
    solver.run(setup.loads)
    assert all(r.converged and r.augmentation_converged for r in solver.records)
    return setup.figures(), setup.dofs


def test_quarter_and_half_disk_agree():
    (q, nq), (h, nh) = figures("quarter"), figures("half")
    assert 1.9 < nh / nq < 2.1  # the half model pays twice the dofs
    assert np.isclose(h["total_force"], h["reaction_top"], rtol=1e-8)
    # different meshes of the same problem: the load within 0.2 %, p0 and a within their mesh error
    assert np.isclose(h["total_force"], q["total_force"], rtol=2e-3)
    assert np.isclose(h["p0"], q["p0"], rtol=1e-2) and np.isclose(h["a"], q["a"], rtol=2e-2)


def _penalty_figures(**kw):
    setup = hertz.build(make_law("penalty", K=1e8), steps=1, **kw)
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    assert all(r.converged for r in solver.records)
    return setup.figures(), setup.dofs


def test_full_disk_and_meshed_plate_against_the_quarter():
    """The quarter disk on the analytic rigid plate (the scene) against the full disk between two rigid plates
    (no mirror) and against a meshed plate 1000 x stiffer (two-body contact), same penalty law."""
    (q, nq), (f, nf), (m, nm) = (_penalty_figures(), _penalty_figures(symmetry="full"),
                                 _penalty_figures(plate="meshed"))
    assert 3.5 < nf / nq < 4.5 and nm > nq  # the full disk: four quarters; the plate adds its own dofs
    # full disk: the two contacts balance (the centre's constraint carries nothing), the load is the quarter's
    assert abs(f["centre_reaction"]) < 1e-3 * f["total_force"]
    assert np.isclose(f["total_force"], q["total_force"], rtol=2e-3)
    assert np.isclose(f["p0"], q["p0"], rtol=1e-2) and np.isclose(f["a"], q["a"], rtol=2e-2)
    # meshed plate: the plate's compliance (1/1000 of the disk's) lowers the load a little, never raises it
    assert 0 < (q["total_force"] - m["total_force"]) / q["total_force"] < 2e-3
    assert np.isclose(m["total_force"], m["reaction_top"], rtol=1e-8)
    assert np.isclose(m["p0"], q["p0"], rtol=3e-3) and np.isclose(m["a"], q["a"], rtol=1e-2)
