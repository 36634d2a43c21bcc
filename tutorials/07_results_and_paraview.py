# %% [markdown]
# # Reading results, writing XDMF, going on after a restart, plotting
#
# The block of the first tutorial with the penalty method `F = K <g>`: the plane's pressure is `K` times the
# penetration, so the block penetrates by `g = p / K`, and the uniform state gives
# `p = d / (H / E* + 1 / K)`, `E* = E / (1 - nu^2)`: the penalty's error is the compliance `1 / K` in series
# with the block's.
#
# Sign conventions, everywhere: the gap `g` is **positive for penetration** (negative: open); the pressure
# is **positive in compression**; `total_force()` is the force of the other side (here the plane) on this
# surface's body, per unit thickness in 2D. Every result call gathers or reduces over the ranks and returns
# the same on each: call it on every rank, print on one.

# %%
import shutil
from pathlib import Path

import numpy as np
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc

E, nu, W, H, d, K = 1000.0, 0.3, 1.0, 2.0, 0.02, 1e4
comm = MPI.COMM_WORLD

mesh = dmesh.create_rectangle(comm, [np.zeros(2), np.array([W, H])], [4, 8])
facets = fc.tag_boundary(mesh, [("base", lambda x: np.isclose(x[1], 0.0)),
                                 ("top", lambda x: np.isclose(x[1], H)),
                                 ("left", lambda x: np.isclose(x[0], 0.0))])
law = fc.make_law("penalty", K=K)
u, V = fc.unknown(mesh, 1, law)
u.name = "displacement"
load = fem.Constant(mesh, 0.0)
contact = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load)
material = fc.LinearElastic(E, nu)
top = fc.Dirichlet.on_facets(V, facets, "top", 1, -d)
problem = fc.ContactProblem(u, material, load, [top, fc.Dirichlet.on_facets(V, facets, "left", 0)], [contact])

# %% [markdown]
# ## The fields to write
#
# `fc.XDMFWriter(path, mesh, functions)` writes the mesh once and the functions at each call of its `write(t)`
# (time = load parameter). Besides the displacement:
#
# - the contact surface's `pressure_out` (`contact_pressure`) and `gap_out` (`gap`): P1 functions that hold the
#   nodal pressure and gap on the contact vertices (0 elsewhere) once `contact.update_output()` has filled them;
# - the stress: any UFL expression interpolated into a function of your own, here the Cauchy stress
#   `material.stress(u)` into a cell-wise constant (DG0) tensor.
#
# The solver's `on_step(t)` is called after each converged load step: fill the fields, then write.

# %%
stress = fem.Function(fc.function_space(mesh, "DG", 0, (2, 2)), name="stress")
fields = [u, contact.pressure_out, contact.gap_out, stress]


def write(t):
    contact.update_output()  # the nodal pressure and gap into pressure_out and gap_out (collective)
    fc.interpolate_expression(stress, material.stress(u))
    writer.write(t)


# %% [markdown]
# ## A run that stops, and goes on
#
# `Solver.run(loads, checkpoint=folder)` saves the converged state after every step. Here the run stops after
# writing the fields of its second step, before its checkpoint (as a killed process would: `kill -9`, a node lost).
# A new solver, made as for the first run (in a new process: the same script), goes back to the last checkpoint
# with `solver.restart(folder)`, which returns the loads still to reach. `fc.XDMFWriter(path, mesh, fields,
# resume=n)` goes on with the same file after step `n`, the steps the checkpoint holds: the later step that the
# stopped run wrote is dropped and written again.

# %%
out = Path("results") / "tutorials" / "block.xdmf"
folder = out.with_name("block_checkpoint")
if comm.rank == 0:
    shutil.rmtree(folder, ignore_errors=True)  # a fresh run: no checkpoint of an earlier one
comm.barrier()


class Stopped(Exception):
    pass


def write_then_stop(t):
    write(t)
    if t == 1.0:
        raise Stopped  # after the fields of step 2, before its checkpoint


with fc.XDMFWriter(out, mesh, fields) as writer:
    try:
        fc.Solver(problem, quiet=True, on_step=write_then_stop).run([0.5, 1.0], checkpoint=folder)
    except Stopped:
        pass

solver = fc.Solver(problem, quiet=True)
pending = solver.restart(folder)  # back to step 1 (t = 0.5); the load 1.0 still to reach
with fc.XDMFWriter(out, mesh, fields, resume=len(solver.records)) as writer:
    solver.on_step = write
    solver.run(pending, checkpoint=folder)

# %% [markdown]
# Open `block.xdmf` in ParaView with an XDMF reader (the mesh is in `block.h5`, each step in a file of its own in
# `block_fields`) and apply *Warp By Vector* with the displacement.
#
# ## The results
#
# - `total_force()`, `tangential_force()`: resultants of the pressure and of the friction;
# - `point_values(reference, kind)`: position (current, or `reference=True`), gap and pressure per contact
#   point; `surface_values(kind)` is `point_values(reference=True, kind)`;
# - `mean_pressure(kind)`: the contact force per area (`nominal` per reference area, `cauchy` per current);
# - `contact_area()`: the closed part of the surface from the gap (a length in 2D);
# - `problem.reaction(dofs)`: the force a Dirichlet support exerts on the body.

# %%
exact = d / (H / (E / (1 - nu**2)) + 1 / K)
x, gap, pressure = contact.point_values()
force = contact.total_force()
reaction = problem.reaction(top.dofs)  # the support pulls the top down: -force
width = contact.contact_area()
if comm.rank == 0:
    print(f"p = {pressure.mean():.10f} (exact {exact:.10f}), penetration {gap.mean():.3e} = p / K, "
          f"force {force[1]:.8f}, reaction at the top {reaction:.8f}, contact width {width:.6f}; wrote {out}")
assert np.allclose(pressure, exact, rtol=1e-8) and np.allclose(gap, exact / K, rtol=1e-8)
assert np.allclose(x[:, 1], -exact / K, atol=1e-12)  # current positions: below the plane by the penetration
assert np.isclose(force[1], exact * W, rtol=1e-8) and np.isclose(reaction, -exact * W, rtol=1e-8)
assert np.isclose(width, W, rtol=1e-12)  # the whole base is closed

# %% [markdown]
# ## Plots without ParaView
#
# `fc.read_xdmf(path)` reads the written series back with h5py (no dolfinx: in any process, after the run):
# the mesh's `points` and `cells`, the steps' `times` and each field per step; `series.at(name, step)` gives
# one step's values (a 2D vector's first two components). It reads files, not the ranks' data: call it on one
# rank. With matplotlib, the pressure and gap along the base, and the deformed mesh coloured by the stress
# `sigma_yy` (with pyvista, if installed, the same `points` and `cells` make a `pyvista.UnstructuredGrid`).

# %%
series = fc.read_xdmf(out)
assert series.times == [0.5, 1.0]  # the restarted file: both steps, the second written once
base = np.isclose(series.points[:, 1], 0.0)  # the contact vertices (reference coordinates)
assert np.allclose(series.at("contact_pressure")[base], exact, rtol=1e-8)
assert np.allclose(series.at("gap")[base], exact / K, rtol=1e-8)
assert np.allclose(series.at("stress")[:, 1, 1], -exact, rtol=1e-6)  # sigma_yy = -p: the uniform state
try:
    import matplotlib
except ImportError:  # pip install matplotlib
    matplotlib = None
pictures = []
if comm.rank == 0 and matplotlib is not None:
    matplotlib.use("Agg")  # files, no window
    import matplotlib.pyplot as plt

    order = np.argsort(series.points[base, 0])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.5))
    ax1.plot(series.points[base, 0][order], series.at("contact_pressure")[base][order], "o-",
             label="contact pressure")
    ax1.plot(series.points[base, 0][order], K * series.at("gap")[base][order], "x--", label="K x gap")
    ax1.set_xlabel("x")
    ax1.set_ylabel("pressure")
    ax1.legend()
    deformed = series.points + 10 * series.at("displacement")  # displacement x 10
    sigma_yy = series.at("stress")[:, 1, 1]  # a DG0 field: one value per cell
    shading = ax2.tripcolor(deformed[:, 0], deformed[:, 1], series.cells, facecolors=sigma_yy, edgecolors="k",
                            linewidth=0.3, vmin=-2 * exact, vmax=0.0)
    fig.colorbar(shading, ax=ax2, label="sigma_yy")
    ax2.set_aspect("equal")
    ax2.set_title("deformed (x 10)")
    pictures.append(out.with_name("block_results.png"))
    fig.tight_layout()
    fig.savefig(pictures[0], dpi=100)
    plt.close(fig)
    print(f"wrote {pictures[0]}")
