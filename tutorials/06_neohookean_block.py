# %% [markdown]
# # Finite strain: a neo-Hookean block, nominal and Cauchy pressure
#
# A compressible neo-Hookean block (`E = 1000`, `nu = 0.3`, plane strain), 1 wide and 2 high, is pressed
# onto a rigid plane by moving its top down by 16 % of its height; its sides are free (a roller on the left).
# The exact state is homogeneous, `F = diag(a, c)` with `c = 1 - 0.16` and, from the free sides
# (`P_xx = 0`), `a^2 = (mu + lambda/2) / (mu + lambda c^2/2)`. The pressure per reference area (nominal) is
# `p = -(mu (c - 1/c) + lambda/2 (J^2 - 1) / c)`, `J = a c`; per current area (Cauchy) it is `p / a`: the
# base widens by `a`.
#
# Pressures are reported nominal by default; `kind="cauchy"` gives the true pressure. Nitsche's method is
# consistent at finite strain: the homogeneous state is the discrete solution.

# %%
import numpy as np
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc

E, nu, W, H, strain = 1000.0, 0.3, 1.0, 2.0, 0.16

mesh = dmesh.create_rectangle(MPI.COMM_WORLD, [np.zeros(2), np.array([W, H])], [4, 8])
facets = fc.tag_boundary(mesh, [("base", lambda x: np.isclose(x[1], 0.0)),
                                 ("top", lambda x: np.isclose(x[1], H)),
                                 ("left", lambda x: np.isclose(x[0], 0.0))])

# %%
law = fc.make_law("nitsche", gamma0=10.0)
u, V = fc.unknown(mesh, 1, law)
load = fem.Constant(mesh, 0.0)
material = fc.NeoHookean(E, nu)  # Nitsche's surface term needs the bulk stress: give the material
contact = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, material=material)
problem = fc.ContactProblem(u, material, load,
                            [fc.Dirichlet.on_facets(V, facets, "top", 1, -strain * H),
                             fc.Dirichlet.on_facets(V, facets, "left", 0)], [contact])
fc.Solver(problem, quiet=True).run([0.25, 0.5, 0.75, 1.0])

# %%
lam, mu = fc.lame(E, nu)
c = 1.0 - strain
a = np.sqrt((mu + lam / 2) / (mu + lam * c**2 / 2))
nominal = -(mu * (c - 1 / c) + lam / 2 * ((a * c) ** 2 - 1) / c)
x, gap, p_nominal = contact.surface_values()
_, _, p_cauchy = contact.surface_values(kind="cauchy")
if MPI.COMM_WORLD.rank == 0:
    print(f"a = {a:.6f}; nominal {p_nominal.mean():.8f} (exact {nominal:.8f}), "
          f"Cauchy {p_cauchy.mean():.8f} (exact {nominal / a:.8f})")
assert np.allclose(p_nominal, nominal, rtol=1e-6)
assert np.allclose(p_cauchy, nominal / a, rtol=1e-6)
assert np.isclose(contact.mean_pressure("cauchy"), nominal / a, rtol=1e-6)
