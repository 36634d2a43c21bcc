# %% [markdown]
# # Reading results and writing XDMF for ParaView
#
# The block of the first tutorial with the penalty method `F = K <g>`: the plane's pressure is `K` times the
# penetration, so the block penetrates by `g = p / K`, and the uniform state gives
# `p = d / (H / E* + 1 / K)`, `E* = E / (1 - nu^2)`: the penalty's error is the compliance `1 / K` in series
# with the block's.
#
# Sign conventions, everywhere: the gap `g` is **positive for penetration** (negative: open); the pressure
# is **positive in compression**; `total_force()` is the force of the other side (here the plane) on this
# surface's body, per unit thickness in 2D. Every result call gathers or reduces over the ranks and returns
# the same on each.

# %%
from pathlib import Path

import numpy as np
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc

E, nu, W, H, d, K = 1000.0, 0.3, 1.0, 2.0, 0.02, 1e4

mesh = dmesh.create_rectangle(MPI.COMM_WORLD, [np.zeros(2), np.array([W, H])], [4, 8])
facets = fc.tag_boundary(mesh, [("base", lambda x: np.isclose(x[1], 0.0)),
                                 ("top", lambda x: np.isclose(x[1], H)),
                                 ("left", lambda x: np.isclose(x[0], 0.0))])

# %% [markdown]
# `fc.XDMFWriter(path, mesh, functions)` writes the mesh once and the functions at each call; the solver's
# `on_step(t)` calls it after each converged load step (time = load parameter). Open `block.xdmf` in ParaView
# and apply *Warp By Vector* to see the deformation.

# %%
law = fc.make_law("penalty", K=K)
u, V = fc.unknown(mesh, 1, law)
u.name = "displacement"
load = fem.Constant(mesh, 0.0)
contact = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load)
top = fc.Dirichlet.on_facets(V, facets, "top", 1, -d)
problem = fc.ContactProblem(u, fc.LinearElastic(E, nu), load, [top, fc.Dirichlet.on_facets(V, facets, "left", 0)],
                            [contact])
out = Path("results") / "tutorials" / "block.xdmf"
with fc.XDMFWriter(out, mesh, [u]) as writer:
    fc.Solver(problem, quiet=True, on_step=writer.write).run([0.5, 1.0])

# %% [markdown]
# The results:
#
# - `total_force()`, `tangential_force()`: resultants of the pressure and of the friction;
# - `point_values(reference, kind)`: position (current, or `reference=True`), gap and pressure per contact
#   point; `surface_values(kind)` is `point_values(reference=True, kind)`;
# - `mean_pressure(kind)`: the contact force per area (`nominal` per reference area, `cauchy` per current);
# - `problem.reaction(dofs)`: the force a Dirichlet support exerts on the body.

# %%
exact = d / (H / (E / (1 - nu**2)) + 1 / K)
x, gap, pressure = contact.point_values()
force = contact.total_force()
reaction = problem.reaction(top.dofs)  # the support pulls the top down: -force
if MPI.COMM_WORLD.rank == 0:
    print(f"p = {pressure.mean():.10f} (exact {exact:.10f}), penetration {gap.mean():.3e} = p / K, "
          f"force {force[1]:.8f}, reaction at the top {reaction:.8f}; wrote {out}")
assert np.allclose(pressure, exact, rtol=1e-8) and np.allclose(gap, exact / K, rtol=1e-8)
assert np.allclose(x[:, 1], -exact / K, atol=1e-12)  # current positions: below the plane by the penetration
assert np.isclose(force[1], exact * W, rtol=1e-8) and np.isclose(reaction, -exact * W, rtol=1e-8)
assert out.is_file() and out.with_suffix(".h5").is_file()  # the index and the mesh
assert len(list(out.with_name(out.stem + "_fields").glob("*.h5"))) == 2  # one file per load step
