"""Run one of dolfinx_contact's own demos (the peer, on dolfinx 0.9) unchanged and measure it: dofs, Newton
iterations, linear solves, Krylov iterations, solver time, and the error against the case's closed form.

Usage (inside the Debian 13 root, the peer importable): ``python3 peer_case.py CASE DEMO OUT.json -- ARGS``
with CASE one of hertz2d, hertz3d, cylinders, wedges, DEMO the demo's file in the peer's source checkout and
ARGS the demo's own options (e.g. ``--res 0.1``).

The demo runs as its author wrote it (``runpy``, ``__name__ == "__main__"``); only its file output (VTX, the
contact writer, which at v0.9.0 also fails on dolfinx 0.9's UFL) is replaced by no-ops, so that its time is
the solver's, as for this suite's ``--no-xdmf`` runs, and the 3D Hertz demo's Dirichlet vertices are flattened
(dolfinx 0.9 refuses its (n, 1) array). Its Newton solver is wrapped to count iterations and
time them. The figures are computed after the run from the demo's own objects (its displacement, contact
problem and closed-form values):

- hertz2d, hertz3d: the peak contact pressure ``p0`` (largest normal traction at the contact quadrature points,
  the peer's own ``compute_contact_forces``) against Hertz's ``p0`` for the demo's load (2D: the demo's ``p0``;
  3D: ``3 P / (2 pi a^2)``, ``a = (3 P R / (4 E*))^(1/3)``, with ``P`` the force the demo applies, its volume
  force and traction integrated over its mesh: the 3D demo's ``load`` is the force on a whole sphere, its
  body the lower half, so ``P`` is about half of it);
- wedges: the horizontal over vertical contact force ``Rx / Ry`` (the demo's own forms) against
  ``(mu + tan alpha) / (1 - mu tan alpha)``;
- cylinders: the stick zone's half-width at the last step (quadrature points of the lower surface in contact
  whose tangential traction is below ``mu p_n``) against Mindlin's ``c = a sqrt(1 - Q / (mu P))`` for the
  demo's final forces (the demo's ``c``).
"""
from __future__ import annotations

import json
import os
import runpy
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

CASES = ("hertz2d", "hertz3d", "cylinders", "wedges")


class _NoWriter:
    """Stands in for VTXWriter: the benchmark times the solver, not the output."""

    def __init__(self, *args, **kwargs):
        pass

    def write(self, *args, **kwargs):
        pass

    def close(self):
        pass


def _instrument() -> dict:
    """Wrap the peer's Newton solver (count and time) and silence its file output; returns the counters."""
    import dolfinx.fem
    import dolfinx.io
    import dolfinx_contact.newton_solver as ns
    import dolfinx_contact.output as output

    stats = {"newton_iterations": 0, "linear_solves": 0, "krylov_iterations": 0, "solves": 0,
             "newton_time_s": 0.0, "converged": True}
    solve = ns.NewtonSolver.solve

    def counted(self, *args, **kwargs):
        t0 = time.perf_counter()
        n, converged = solve(self, *args, **kwargs)
        stats["newton_time_s"] += time.perf_counter() - t0
        stats["newton_iterations"] += int(n)
        stats["linear_solves"] += int(n)  # one Krylov solve per Newton iteration (no line-search solves)
        stats["krylov_iterations"] += int(self.krylov_iterations)
        stats["solves"] += 1
        stats["converged"] = stats["converged"] and bool(converged)
        return n, converged

    ns.NewtonSolver.solve = counted
    # The 3D Hertz demo (v0.9.0) passes its Dirichlet vertices as an (n, 1) array, which dolfinx 0.9 refuses
    # (its 2D branch flattens them with np.hstack): flattened here, nothing else changed.
    # dolfinx 0.9 also needs the entity-to-cell connectivity made first (the cylinders demo locates vertex dofs
    # without it).
    locate = dolfinx.fem.locate_dofs_topological

    def locate_flat(V, dim, entities, remote=True):
        topology = V.mesh.topology
        topology.create_connectivity(dim, topology.dim)
        return locate(V, dim, np.asarray(entities, dtype=np.int32).reshape(-1), remote)

    dolfinx.fem.locate_dofs_topological = locate_flat
    dolfinx.io.XDMFFile.read_meshtags = _writable_tags(dolfinx.io.XDMFFile.read_meshtags)
    dolfinx.io.VTXWriter = _NoWriter
    ns.VTXWriter = _NoWriter
    output.VTXWriter = _NoWriter
    # The contact writer projects tractions for output (and at v0.9.0 fails on dolfinx 0.9's UFL:
    # ufl.FiniteElement is gone); the figures are computed here instead.
    output.ContactWriter = _NoWriter
    return stats


class _TagValues(np.ndarray):
    """A writable copy of a MeshTags' values that writes every assignment back to its tags."""

    _owner = None  # the tags (arrays derived from this one, e.g. comparisons, have none)

    def __array_finalize__(self, obj):
        self._owner = None

    def __setitem__(self, key, value):
        super().__setitem__(key, value)
        if self._owner is not None:
            self._owner._rebuild()


def _writable_tags(read):
    """``XDMFFile.read_meshtags`` returning tags whose ``values`` can be assigned in place, as the peer's demos
    (written for an earlier dolfinx) do: dolfinx 0.9 hands out a read-only view of them. Each assignment makes
    the tags anew from the same entities and the new values (the C++ object the demo passes on)."""
    from dolfinx.mesh import MeshTags

    class WritableTags(MeshTags):
        def __init__(self, cpp):
            super().__init__(cpp)
            self._values = np.array(cpp.values).view(_TagValues)
            self._values._owner = self

        @property
        def values(self):
            return self._values

        def _rebuild(self):
            cpp = self._cpp_object
            new = type(cpp)(cpp.topology, cpp.dim, np.array(cpp.indices, dtype=np.int32),
                            np.asarray(self._values).copy())
            new.name = cpp.name
            self._cpp_object = new

    def wrapped(self, mesh, name, *args, **kwargs):
        return WritableTags(read(self, mesh, name, *args, **kwargs)._cpp_object)

    return wrapped


def _tractions(g: dict, pair: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Normal and tangential contact traction magnitudes and the physical coordinates (reference configuration)
    at the quadrature points of ``pair``'s surface, as the peer's own writer computes them."""
    import dolfinx_contact.cpp as cpp
    from dolfinx.fem import Function, functionspace

    problem, u, mesh = g["contact_problem"], g["u"], g["mesh"]
    gdim = mesh.geometry.dim
    mu_fn, lmbda_fn = g.get("mu_dg", g.get("mu")), g.get("lmbda_dg", g.get("lmbda"))
    lame = [float(np.max(f.x.array)) if hasattr(f, "x") else float(f) for f in (mu_fn, lmbda_fn)]
    problem.update_contact_detection(u)
    entities = problem.entities[pair]
    n_y = np.array(problem.pack_ny(pair)).reshape(len(entities), -1, gdim)
    n_x = problem.pack_nx(pair)
    grad_u = cpp.pack_gradient_quadrature(u._cpp_object, problem.q_deg, entities)
    nq = n_y.shape[1]
    s = np.array(cpp.compute_contact_forces(grad_u.reshape(-1), np.asarray(n_x).reshape(-1), nq, len(entities),
                                            gdim, lame[0], lame[1])).reshape(len(entities), nq, gdim)
    pn = np.sum(s * n_y, axis=2)
    pt = np.linalg.norm(s - n_y * pn[:, :, None], axis=2)
    X = Function(functionspace(mesh, ("Lagrange", 1, (gdim,))))
    X.interpolate(lambda x: x[:gdim])
    xq = np.array(cpp.pack_coefficient_quadrature(X._cpp_object, problem.q_deg, entities)).reshape(-1, gdim)
    return np.abs(pn).reshape(-1), pt.reshape(-1), xq


def _applied_force(g: dict) -> float:
    """The downward force the 3D Hertz demo applies at its last step: its volume force over its sphere's cells
    (``dx(1)``) plus its traction over its loaded facets (``ds(neumann_bdy)``)."""
    from dolfinx import fem
    from mpi4py import MPI

    f, t, dx, ds = g["f"], g["t"], g["dx"], g["ds"]
    form = fem.form(-f[2] * dx(1) - t[2] * ds(g["neumann_bdy"]))
    return float(MPI.COMM_WORLD.allreduce(fem.assemble_scalar(form), op=MPI.SUM))


def _figures(case: str, g: dict) -> dict:
    if case in ("hertz2d", "hertz3d"):
        p0 = max(float(np.max(_tractions(g, i)[0])) for i in range(2))
        P, R, Es = float(g["load"]), float(g["R"]), float(g["Estar"])
        if case == "hertz2d":  # the demo's own closed form (its last load step is the whole load)
            a, ref = float(g["a"]), float(g["p0"])
        else:  # the demo's load loop overwrites a and p0 with the 2D formulas: Hertz's sphere here
            P = _applied_force(g)
            a = float(np.cbrt(3 * P * R / (4 * Es)))
            ref = 3 * P / (2 * np.pi * a**2)
        return {"figure": "p0", "value": p0, "reference": ref, "error": abs(p0 - ref) / ref, "a_hertz": a,
                "load": P}
    if case == "wedges":
        fric, angle = float(g["fric"]), float(g["angle"])
        ratio = abs(float(g["R_x1"])) / abs(float(g["R_y1"]))
        ref = (fric + np.tan(angle)) / (1 - fric * np.tan(angle))
        return {"figure": "Rx/Ry", "value": ratio, "reference": float(ref), "error": abs(ratio - ref) / ref,
                "ratio_other_surface": abs(float(g["R_x2"])) / abs(float(g["R_y2"]))}
    if case == "cylinders":
        fric, c_ref, a_ref = float(g["fric"]), float(g["c"]), float(g["a"])
        pn, pt, xq = _tractions(g, 1)  # the lower cylinder's surface
        # The stress at the free surface's quadrature points is not exactly traction-free: the contact zone is
        # taken around the pressure's centroid, within the demo's Hertz half-width a (its points pressed).
        pressed = pn > 0.1 * pn.max()
        centre = float(np.sum(xq[pressed, 0] * pn[pressed]) / np.sum(pn[pressed]))
        closed = (np.abs(xq[:, 0] - centre) < a_ref) & (pn > 0)
        x = xq[closed, 0]
        stick = pt[closed] < (1 - 1e-3) * fric * pn[closed]
        c = float(np.max(np.abs(x[stick] - centre))) if stick.any() else 0.0
        return {"figure": "c", "value": c, "reference": c_ref, "error": abs(c - c_ref) / c_ref,
                "a": float(np.max(np.abs(xq[pressed, 0] - centre))), "a_hertz": a_ref,
                "Q_over_muP": float(g["q"]) / (fric * float(g["pr"]))}
    raise ValueError(f"case must be one of {CASES}, got {case!r}")


def main(argv: list[str]) -> int:
    if "--" in argv:
        i = argv.index("--")
        argv, demo_args = argv[:i], argv[i + 1:]
    else:
        demo_args = []
    if len(argv) != 3 or argv[0] not in CASES:
        print(f"usage: peer_case.py CASE DEMO OUT.json -- ARGS (CASE one of {', '.join(CASES)})", file=sys.stderr)
        return 2
    case, demo, out = argv[0], Path(argv[1]).resolve(), Path(argv[2]).resolve()
    if not demo.is_file():
        print(f"DEMO: no such file {demo}", file=sys.stderr)
        return 2
    stats = _instrument()
    from mpi4py import MPI

    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp, "work")
        for d in ("work/meshes", "work/results", "meshes", "results"):
            Path(tmp, d).mkdir(parents=True)
        os.chdir(work)
        sys.argv = [str(demo), *demo_args]
        t0 = time.perf_counter()
        g = runpy.run_path(str(demo), run_name="__main__")
        total = time.perf_counter() - t0
        V = g["V"]
        dofs = V.dofmap.index_map.size_global * V.dofmap.index_map_bs
        figures = _figures(case, g)
    row = {"code": "dolfinx_contact", "case": case, "demo": demo.name, "args": demo_args, "dofs": int(dofs),
           "ranks": MPI.COMM_WORLD.size, **stats, "wall_time_s": stats["newton_time_s"], "total_time_s": total,
           **figures}
    if MPI.COMM_WORLD.rank == 0:
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(json.dumps(row, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
