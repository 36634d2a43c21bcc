# %% [markdown]
# # Force control from rest: a traction and the vanishing spring
#
# The block of the first tutorial, now loaded by a pressure `q` on its top instead of a displacement. The
# left side is a roller (`u_x = 0`), nothing else holds the block vertically but the contact: at rest, before
# the contact has closed, the problem is singular (a free rigid motion). The cure is a spring
# `k (1 - t) u` on the whole body that vanishes at the last load step `t = 1`: it holds the block in the
# steps before, and the answer at `t = 1` is that of the pure force-controlled problem.
#
# Tractions are `ContactProblem(..., tractions=[(vector, ds(tag)), ...])`, scaled by the load parameter
# `t` (an entry `(vector, ds(tag), path)` follows another load path: the guide's page on loads).
# `fc.Stabilised` is the `ContactProblem` with that spring (one more load-scaled term, `(-s u, dx)` with
# `s = k (1 - t) / t`, updated at every load step).

# %%
import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc

E, nu, W, H, q = 1000.0, 0.3, 1.0, 2.0, 5.0

# %% [markdown]
# A rectangle of dolfinx's own is enough here; `fc.tag_boundary` names its sides.

# %%
mesh = dmesh.create_rectangle(MPI.COMM_WORLD, [np.zeros(2), np.array([W, H])], [4, 8])
facets = fc.tag_boundary(mesh, [("base", lambda x: np.isclose(x[1], 0.0)),
                                 ("top", lambda x: np.isclose(x[1], H)),
                                 ("left", lambda x: np.isclose(x[0], 0.0))])
ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets.meshtags)


# %%
law = fc.make_law("auglag", K=1e5)
u, V = fc.unknown(mesh, 1, law)
load = fem.Constant(mesh, 0.0)
contact = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load)
problem = fc.Stabilised(u, fc.LinearElastic(E, nu), load, [fc.Dirichlet.on_facets(V, facets, "left", 0)], [contact],
                        tractions=[(fem.Constant(mesh, np.array([0.0, -q])), ds(facets["top"]))], k=E / H**2,
                        dx_body=ufl.dx(domain=mesh))
fc.Solver(problem, quiet=True, augment_max=20, augment_tol=1e-10).run([0.25, 0.5, 0.75, 1.0])

# %% [markdown]
# At `t = 1` the spring is gone: the plane carries the whole load, `q` per unit area, uniformly.

# %%
x, gap, pressure = contact.surface_values()
force = contact.total_force()
if MPI.COMM_WORLD.rank == 0:
    print(f"force {force[1]:.10f} (q W = {q * W}), pressure {pressure.min():.8f} .. {pressure.max():.8f}")
assert np.isclose(force[1], q * W, rtol=1e-8)
assert np.allclose(pressure, q, rtol=1e-6)
