# %% [markdown]
# # Coulomb friction, exact: a block dragged on a rigid plane
#
# A block, 2 wide and 1 high, on a rigid plane with Coulomb friction `mu = 0.3`. Its top is first moved
# down by `d` (`t` from 0 to 1), then along the plane by `s` (`t` from 1 to 2): a displacement with a load
# path. Once every contact point slips, the friction force is `mu` times the normal force exactly.
#
# Method `coulomb` (`fc.ExactCoulomb(mu)`) solves the Signorini-Coulomb conditions exactly on the
# stiffness condensed onto the contact nodes; it solves whole load steps itself (the problem takes the
# step solver the surface needs, `fc.step_solver_for(contacts)`, instead of SNES). It works in 2D and 3D
# with linear elasticity, against a flat rigid obstacle or between two bodies in small sliding. Friction is
# path dependent: take load steps.

# %%
import numpy as np
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc

E, nu, W, H, mu, d, s = 1000.0, 0.3, 2.0, 1.0, 0.3, 0.01, 0.05

mesh = dmesh.create_rectangle(MPI.COMM_WORLD, [np.zeros(2), np.array([W, H])], [16, 8])
facets = fc.tag_boundary(mesh, [("base", lambda x: np.isclose(x[1], 0.0)),
                                 ("top", lambda x: np.isclose(x[1], H))])

# %% [markdown]
# A `Dirichlet`'s `path = (t_k, f_k)` makes its value `amplitude * f(t)`, `f` piecewise linear.

# %%
law = fc.ExactCoulomb(mu)
u, V = fc.unknown(mesh, 1, law)
load = fem.Constant(mesh, 0.0)
contact = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load)
down = fc.Dirichlet.on_facets(V, facets, "top", 1, -d, path=([0.0, 1.0], [0.0, 1.0]))  # down by d at t = 1, held
along = fc.Dirichlet.on_facets(V, facets, "top", 0, s, path=([1.0, 2.0], [0.0, 1.0]))  # then along by s
problem = fc.ContactProblem(u, fc.LinearElastic(E, nu), load, [down, along], [contact])
fc.Solver(problem, quiet=True).run([0.5, 1.0, 1.25, 1.5, 1.75, 2.0])

# %% [markdown]
# `friction_profile()` gives, per contact point, the pressure, the tangential traction and the state
# (0 open, 1 slip, 2 stick); `tangential_force()` the resultant of the friction on the block.

# %%
normal, tangential = contact.total_force(), contact.tangential_force()
profile = contact.friction_profile()
ratio = abs(tangential[0]) / normal[1]
if MPI.COMM_WORLD.rank == 0:
    print(f"N = {normal[1]:.6f}, T = {tangential[0]:.6f}, T / N = {ratio:.10f} (mu = {mu}); "
          f"states {np.bincount(profile['state'].astype(int), minlength=3)} (open, slip, stick)")
assert not np.any(profile["state"] == 2)  # no point sticks (a corner may lift off)
assert np.isclose(ratio, mu, rtol=1e-8)
