"""FElupe's side of the side-by-side run (scripts/felupe/run.py): an O-ring cord of diameter ``d`` squeezed
between two rigid frictionless plates, plane strain or axisymmetric, run by FElupe in its own venv; prints
nothing, writes one JSON file.

    python felupe_case.py OUT.json --plane axisymmetric --n 20 --squeeze 0.05 0.1 ... [--d 1 --r-in 5 --E 1000
        --nu 0.4999 --multiplier 100]

The cord: the half disk ``z >= 0`` of FElupe's quadrilateral circle mesh (``n`` points on a 45-degree edge),
centred at ``(r_in + d/2, 0)``, ``u_z = 0`` on ``z = 0`` (the symmetry of the problem). The rubber: FElupe's
isochoric ``NeoHooke(mu)`` on a ``SolidBodyNearlyIncompressible`` of bulk modulus ``kappa = lambda + 2 mu / 3``
(the energy ``mu/2 (I1_bar - 3) + kappa/2 (J_bar - 1)^2``, mean dilatation on bilinear quadrilaterals). The plates:
two ``ContactRigidPlane`` (node-to-plane penalty, its multiplier scaled by the mean stiffness of the solid at the
contact points), the groove bottom ``r = r_in`` fixed, the bore ``r = r_in + d`` moved toward the axis by
``squeeze d``. Plane strain: the cord's centre held at ``u_r = 0`` (both plates move by ``squeeze d / 2``, the
symmetric equivalent of one moving plate: frictionless walls leave the translation free); axisymmetric: the ring's
hoop stiffness holds its radial position, the bottom fixed and the bore moving as in the suite's scene.

Per squeeze: the bore's force per unit circumference (axisymmetric: the ring's force over ``2 pi r_bore``; plane
strain: per unit length, the whole cord), the bore's nodal contact pressures (nodal force over the node's share of
the current contact line, times ``2 pi r`` in axisymmetry) with the nodes' current axial coordinate (both halves of
the cord: mirrored), the largest penetration, Newton iterations and time.
"""
from __future__ import annotations

import argparse
import json
import time

import numpy as np


def nodal_pressure(y: np.ndarray, x: np.ndarray, nodes: np.ndarray, force: np.ndarray,
                   axisymmetric: bool) -> tuple[np.ndarray, np.ndarray]:
    """The nodal pressures of a plate on the configuration ``y`` (current: Cauchy; reference: nominal): each node's
    force over its share of the contact line (half its two neighbours' segments; on the cut its half of the share
    and half its force, the mirror carrying the rest), times ``2 pi r`` in axisymmetry (FElupe's forces are the
    ring's); with the nodes' current axial coordinates (of ``x``), both halves of the cord, sorted."""
    order = np.argsort(y[nodes, 0])
    zs, rs, fs = y[nodes, 0][order], y[nodes, 1][order], force[order]
    seg = np.hypot(np.diff(zs), np.diff(rs))
    tributary = np.zeros_like(zs)
    tributary[:-1] += 0.5 * seg
    tributary[1:] += 0.5 * seg
    weight = 2 * np.pi * rs if axisymmetric else np.ones_like(rs)
    p = np.where(fs > 0, fs / (tributary * weight), 0.0)
    z = x[nodes, 0][order]
    return np.concatenate([-z[:0:-1], z]), np.concatenate([p[:0:-1], p])


def run(plane: str, n: int, squeezes: list[float], d: float, r_in: float, E: float, nu: float,
        multiplier: float) -> dict:
    import felupe as fem

    rc = r_in + 0.5 * d
    mu = E / (2 * (1 + nu))
    kappa = E * nu / ((1 + nu) * (1 - 2 * nu)) + 2 * mu / 3
    # FElupe's axisymmetric coordinates are (axial, radial): the mesh is built as (z, r), its cells reordered to
    # keep their orientation after the swap
    disk = fem.mesh.Circle(radius=0.5 * d, centerpoint=[0.0, 0.0], n=n, sections=[0, 90])
    zr = np.column_stack([np.maximum(disk.points[:, 1], 0.0), rc + disk.points[:, 0]])
    npts = len(zr)
    mesh = fem.Mesh(np.vstack([zr, [[0.0, r_in], [0.0, r_in + d]]]), disk.cells[:, ::-1].copy(), "quad")
    bottom_c, bore_c = npts, npts + 1
    region = fem.RegionQuad(mesh)
    field = fem.FieldContainer([(fem.FieldAxisymmetric if plane == "axisymmetric" else fem.FieldPlaneStrain)(
        region, dim=2)])
    u = field[0]
    solid = fem.SolidBodyNearlyIncompressible(fem.NeoHooke(mu=mu), field, bulk=kappa)
    X = mesh.points
    index = np.arange(mesh.npoints)
    rim = np.where(np.isclose(np.hypot(X[:npts, 1] - rc, X[:npts, 0]), 0.5 * d, rtol=1e-8, atol=0))[0]
    inner = rim[X[rim, 1] <= rc]
    outer = rim[X[rim, 1] >= rc]
    kw = {"items": [solid], "multiplier": multiplier}
    c_bottom = fem.ContactRigidPlane(field, inner, bottom_c, normal=[0.0, 1.0], **kw)
    c_bore = fem.ContactRigidPlane(field, outer, bore_c, normal=[0.0, -1.0], **kw)
    boundaries = {"symmetry": fem.Boundary(u, mask=np.isclose(X[:, 0], 0.0) & (index < npts), skip=(0, 1)),
                  "bottom_z": fem.Boundary(u, mask=index == bottom_c, skip=(0, 1)),
                  "bottom": fem.Boundary(u, mask=index == bottom_c, skip=(1, 0)),
                  "bore_z": fem.Boundary(u, mask=index == bore_c, skip=(0, 1)),
                  "bore": fem.Boundary(u, mask=index == bore_c, skip=(1, 0))}
    table = np.array(squeezes) * d
    if plane == "axisymmetric":
        ramp = {boundaries["bore"]: -table}
    else:
        centre = np.isclose(X[:, 1], rc) & np.isclose(X[:, 0], 0.0) & (index < npts)
        boundaries["centre"] = fem.Boundary(u, mask=centre, skip=(1, 0))
        ramp = {boundaries["bore"]: -0.5 * table, boundaries["bottom"]: 0.5 * table}
    step = fem.Step(items=[solid, c_bottom, c_bore], ramp=ramp, boundaries=boundaries)
    rows = []
    t0 = time.perf_counter()
    tlast = t0
    for s, res in zip(squeezes, step.generate(x0=field, tol=1e-9, verbose=0)):
        x = X + u.values
        f = np.asarray(c_bore.results.force.toarray()).reshape(-1, 2)
        r_bore = x[bore_c, 1]
        f_nodes = f[outer, 1]  # the residual's share, lambda_n g n: the plate's force on the cord, toward the axis
        axi = plane == "axisymmetric"
        along, cauchy = nodal_pressure(x, x, outer, f_nodes, axi)
        _, nominal = nodal_pressure(X, x, outer, f_nodes, axi)
        total = 2 * f_nodes.sum()  # both halves of the cord
        penetration = float(np.max(np.maximum(x[outer, 1] - r_bore, 0.0), initial=0.0))
        per = 2 * np.pi * r_bore if plane == "axisymmetric" else 1.0
        now = time.perf_counter()
        rows.append({"squeeze": s, "force_bore": total / per, "along": along.tolist(),
                     "pressure": cauchy.tolist(), "pressure_nominal": nominal.tolist(), "penetration": penetration / d,
                     "newton_iterations": int(res.iterations), "converged": bool(res.success),
                     "step_time_s": now - tlast})
        tlast = now
    return {"code": "felupe", "version": fem.__version__, "plane": plane, "n": n,
            "dofs": int(u.values.size), "cells": int(mesh.ncells), "wall_time_s": time.perf_counter() - t0,
            "rows": rows}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out")
    p.add_argument("--plane", choices=("axisymmetric", "strain"), required=True)
    p.add_argument("--n", type=int, required=True)
    p.add_argument("--squeeze", type=float, nargs="+", required=True)
    p.add_argument("--d", type=float, default=1.0)
    p.add_argument("--r-in", type=float, default=5.0)
    p.add_argument("--E", type=float, default=1000.0)
    p.add_argument("--nu", type=float, default=0.4999)
    p.add_argument("--multiplier", type=float, default=100.0)
    a = p.parse_args()
    out = run(a.plane, a.n, a.squeeze, a.d, a.r_in, a.E, a.nu, a.multiplier)
    with open(a.out, "w") as fh:
        json.dump(out, fh)


if __name__ == "__main__":
    main()
