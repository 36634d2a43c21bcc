"""Bad input gets a clear error; a step that cannot converge raises after the last converged step is on disk."""
import dataclasses
import json
import re

import pytest
from dolfinx import fem
from mpi4py import MPI

from fenics_contact.app.meshes import rectangle
from fenics_contact.app.run import run
from fenics_contact.app.scenes import block
from fenics_contact.compat import function_space
from fenics_contact.contact import ContactSurface
from fenics_contact.laws import Penalty
from fenics_contact.materials import LinearElastic
from fenics_contact.obstacles import Ball, HalfPlane
from fenics_contact.solver import ConvergenceError


def _u(comm):
    mesh, _, tags = rectangle(comm, 1.0, 1.0, 2, 2)
    return fem.Function(function_space(mesh, "Lagrange", 1, (2,))), tags


def test_absent_facet_tag_is_named(comm):
    u, tags = _u(comm)
    load = fem.Constant(u.function_space.mesh, 0.0)
    with pytest.raises(ValueError, match="facet tag 'contact'=99 is absent from the mesh"):
        ContactSurface(u, tags, 99, HalfPlane([0, 0], [0, 1]), Penalty(1e5), load)


def test_mesh_without_facet_tags(comm):
    u, _ = _u(comm)
    load = fem.Constant(u.function_space.mesh, 0.0)
    with pytest.raises(ValueError, match="no facet tags"):
        ContactSurface(u, None, 1, HalfPlane([0, 0], [0, 1]), Penalty(1e5), load)


def test_unknown_quadrature(comm):
    u, tags = _u(comm)
    load = fem.Constant(u.function_space.mesh, 0.0)
    with pytest.raises(ValueError, match="contact quadrature"):
        ContactSurface(u, tags, "bottom", HalfPlane([0, 0], [0, 1]), Penalty(1e5), load, quadrature="lobatto")


@pytest.mark.parametrize("E,nu,name", [(-1.0, 0.3, "Young's modulus"), (1.0, 0.5, "Poisson's ratio")])
def test_bad_material(E, nu, name):
    with pytest.raises(ValueError, match=name):
        LinearElastic(E, nu)


def test_bad_obstacle():
    with pytest.raises(ValueError, match="radius"):
        Ball([0, 0], -1.0)
    with pytest.raises(ValueError, match="normal"):
        HalfPlane([0, 0], [0, 0])


def test_failed_step_raises_after_writing_the_last_converged_state(tmp_path_factory, comm):
    out = comm.bcast(str(tmp_path_factory.mktemp("fail")) if comm.rank == 0 else None)
    setup = block.build(Penalty(1e5), comm=comm)
    # t = 1e-16 converges at iteration 0 (residual below atol); no Newton step is allowed after it
    setup = dataclasses.replace(setup, loads=[1e-16, 1.0])
    with pytest.raises(ConvergenceError, match=r"load step 2 .* did not converge after 4 cutbacks"):
        run(setup, out, "penalty", {}, quiet=True, options={"snes_max_it": 0})
    summary = json.load(open(f"{out}/summary.json"))
    assert summary["converged"] is False and summary["load_steps"] == 1 and "cutbacks" in summary["error"]
    times = re.findall(r'Time Value="([^"]+)"', open(f"{out}/block.xdmf").read())
    assert times and all(float(t) == 1e-16 for t in times)  # only the converged step
    assert MPI.COMM_WORLD.allreduce(1) == comm.size
