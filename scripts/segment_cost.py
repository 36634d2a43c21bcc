"""Cost of segment (mortar-type) integration: seconds per residual and per Jacobian of the contact terms.

    python scripts/segment_cost.py [hertz_twobody] [sphere_block] [--level 0] [--repeat 3]

Solves the scene with ``quadrature="segment"`` (penalty, the bench's K), then at the converged state times the
surface's update (projection and pairing), its residual (``add_residual``) and its tangent
(``coupling_matrices``, after the residual of the same state, as in a Newton iteration), the best of
``--repeat`` calls each, and prints them with the number of sub-segment pairs and the residual's norm (to
compare versions).
"""
from __future__ import annotations

import argparse
import tempfile
import time

import numpy as np
from mpi4py import MPI

import fenics_contact as fc
import fenics_contact.app as app
from fenics_contact.app.cli import LINEAR_SOLVERS

SCENES = {
    "hertz_twobody": ("hertz", dict(plate="meshed", E=200.0, nu=0.3, R=8.0, load=10.0, plate_E=200.0,
                                    plate_width=32.0, plate_depth=16.0), 2.5e4, "direct"),
    "sphere_block": ("sphere", dict(plate="meshed"), None, "iterative"),
}


def best(f, repeat: int, comm) -> float:
    times = []
    for _ in range(repeat):
        comm.barrier()
        t0 = time.perf_counter()
        f()
        times.append(comm.allreduce(time.perf_counter() - t0, op=MPI.MAX))
    return min(times)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scenes", nargs="*", default=list(SCENES), choices=list(SCENES))
    p.add_argument("--level", type=int, default=0, help="refinement (hertz) or level (sphere)")
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--pressed", type=float, default=None,
                   help="no solve: the upper body (reference height above 0) moved down by this much instead")
    args = p.parse_args()
    comm = MPI.COMM_WORLD
    for name in args.scenes:
        measure(name, args, comm)


def measure(name: str, args, comm) -> None:
    scene, kw, K, solver = SCENES[name]
    module = __import__(f"fenics_contact.app.scenes.{scene}", fromlist=["DEFAULT_K"])
    K = K or module.DEFAULT_K
    size_kw = {"refinement": args.level} if scene == "hertz" else {"level": args.level}
    setup = app.build(scene, law=fc.make_law("penalty", K=K), quadrature="segment", **size_kw, **kw)
    problem = setup.problem
    c = setup.contacts[0]
    if args.pressed is None:
        with tempfile.TemporaryDirectory() as out:
            summary = app.run(setup, out, "penalty", {"K": K}, quiet=True, options=dict(LINEAR_SOLVERS[solver]),
                             xdmf=False)
    else:  # a rigid motion of the upper body into the lower one: contact pairs without a solve
        V = problem.u.function_space
        d = V.mesh.geometry.dim
        x = V.tabulate_dof_coordinates()[:, :d]
        u = problem.u.x.array.reshape(-1, d)
        u[:, d - 1] = np.where(x[:, d - 1] > 1e-9, -args.pressed, 0.0)
        problem.u.x.scatter_forward()
        summary = {"newton_iterations": 0, "p0": float("nan")}
    b = problem.create_vector()
    t_update = best(lambda: c.update(), args.repeat, comm)

    def residual():
        c._element_cache = None  # a new state, as in a Newton iteration (the element routine runs)
        b.set(0.0)
        c.add_residual(b)

    def jacobian():  # after the residual of the same state, as in a Newton iteration
        c.coupling_matrices(problem.bcs)

    t_res = best(residual, args.repeat, comm)
    t_jac = best(lambda: (residual(), jacobian()), args.repeat, comm) - t_res
    residual()
    pairs = comm.allreduce(len(c._segment_pairs))
    if comm.rank == 0:
        print(f"{name} ({setup.dofs} dofs, {comm.size} ranks): Newton {summary['newton_iterations']}, "
              f"p0 {summary['p0']:.10g}, {pairs} sub-segment pairs, |R_contact| {b.norm():.12e}")
        print(f"  update {t_update:.4f} s  residual {t_res:.4f} s  Jacobian {t_jac:.4f} s  "
              f"residual + Jacobian {t_res + t_jac:.4f} s")

if __name__ == "__main__":
    main()
