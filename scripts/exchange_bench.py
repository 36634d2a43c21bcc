"""Master-surface exchange of the two-body surfaces: the former all-gather against the box exchange.

    mpirun -n 2 python scripts/exchange_bench.py [hertz_twobody] [sphere_block] [--refinement 0]

Solves each scene twice in one process, with ``TwoBodySurface.exchange = "allgather"`` (every master facet to
every rank: the former scheme's traffic) and ``"boxes"`` (only to the ranks whose grown slave box it overlaps),
and prints per mode: updates, bytes received from other ranks (largest rank; the former MPI_Allgather's bytes
as the surface counts them), master facets received per update, exchange seconds (largest rank), the figures
and their largest difference between the two modes.
"""
from __future__ import annotations

import argparse
import tempfile

import numpy as np
from mpi4py import MPI

import fenics_contact as fc
import fenics_contact.app as app
from fenics_contact.app.cli import LINEAR_SOLVERS
from fenics_contact.twobody import TwoBodySurface

SCENES = {
    "hertz_twobody": ("hertz", dict(plate="meshed", E=200.0, nu=0.3, R=8.0, load=10.0, plate_E=200.0,
                                    plate_width=32.0, plate_depth=16.0), 2.5e4, "direct"),
    "sphere_block": ("sphere", dict(plate="meshed"), None, "iterative"),
}


def measure(name: str, mode: str, level: int, quadrature: str) -> dict:
    scene, kw, K, solver = SCENES[name]
    module = __import__(f"fenics_contact.app.scenes.{scene}", fromlist=["DEFAULT_K"])
    K = K or module.DEFAULT_K
    TwoBodySurface.exchange = mode
    size_kw = {"refinement": level} if scene == "hertz" else {"level": level}
    setup = app.build(scene, law=fc.make_law("penalty", K=K), quadrature=quadrature, **size_kw, **kw)
    with tempfile.TemporaryDirectory() as out:
        summary = app.run(setup, out, "penalty", {"K": K}, quiet=True, options=dict(LINEAR_SOLVERS[solver]),
                         xdmf=False)
    comm = setup.problem.comm
    stats = [c.exchange_stats() for c in setup.contacts]
    total = {k: sum(s[k] for s in stats) for k in stats[0]}
    return {"dofs": setup.dofs, "newton": summary["newton_iterations"], "p0": summary["p0"],
            "updates": total["updates"], "reroutes": total.get("reroutes", 0),
            "bytes": comm.allreduce(total["bytes_received"], op=MPI.MAX),
            "allgather_bytes": comm.allreduce(total["allgather_bytes"], op=MPI.MAX),
            "facets_per_update": comm.allreduce(total["facets_received"], op=MPI.MAX) / max(total["updates"], 1),
            "exchange_s": comm.allreduce(total["seconds"], op=MPI.MAX),
            "split_exchange_s": summary["time_split"].get("exchange_s"),
            "points": [c.point_values()[2] for c in setup.contacts]}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scenes", nargs="*", default=list(SCENES), choices=list(SCENES))
    p.add_argument("--level", type=int, default=0, help="refinement (hertz) or level (sphere)")
    p.add_argument("--quadrature", default="nodal", choices=["nodal", "gauss", "segment"])
    args = p.parse_args()
    comm = MPI.COMM_WORLD
    for name in args.scenes:
        rows = {mode: measure(name, mode, args.level, args.quadrature) for mode in ("allgather", "boxes")}
        a, b = rows["allgather"], rows["boxes"]
        diff = max(float(np.max(np.abs(x - y), initial=0.0)) for x, y in zip(a["points"], b["points"]))
        if comm.rank == 0:
            print(f"{name} ({a['dofs']} dofs, {comm.size} ranks, {args.quadrature}): largest pressure difference "
                  f"between the modes {diff:.2e}, p0 {a['p0']:.10g} / {b['p0']:.10g}")
            for mode, r in rows.items():
                print(f"  {mode:9s} updates {r['updates']:3d} (routes {r['reroutes']})  received "
                      f"{r['bytes'] / 1e3:9.1f} kB (all-gather "
                      f"would: {r['allgather_bytes'] / 1e3:9.1f} kB)  master facets per update "
                      f"{r['facets_per_update']:8.1f}  exchange {r['exchange_s']:.4f} s  Newton {r['newton']}")


if __name__ == "__main__":
    main()
