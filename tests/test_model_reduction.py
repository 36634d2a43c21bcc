"""Model reduction on hertz: the quarter disk and the half disk solve the same problem."""
import numpy as np

from fenics_contact.laws import make_law
from fenics_contact.scenes import hertz
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
