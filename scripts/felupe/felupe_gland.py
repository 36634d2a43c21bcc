"""FElupe's side of the gland case of the side-by-side run (scripts/felupe/run.py): an O-ring cord of diameter
``d`` in a rigid rectangular gland, squeezed, then pressurised on one side (the suite's ``oring`` scene), plane
strain or axisymmetric, run by FElupe in its own venv; prints nothing, writes one JSON file.

    python felupe_gland.py OUT.json --plane axisymmetric --n 19 [--d 1 --r-in 5 --E 1000 --nu 0.4999
        --squeeze 0.3 --squeeze-steps 3 --gland-width 1.5 --pressure 100 --pressure-arc 40 --multiplier 100]

The cord: FElupe's quadrilateral circle mesh (``n`` points on a 45-degree edge, uniform in angle round the rim:
the ends of the loaded arc are nodes if ``8 (n - 1) (pressure_arc / 360)`` is an integer), the whole disk centred at
``(r_in + d/2, 0)``. The rubber as in felupe_case.py (``NeoHooke`` on a ``SolidBodyNearlyIncompressible``). The
gland: four ``ContactRigidPlane`` against every rim node (any node may touch any wall): the groove bottom ``r =
r_in`` (fixed), the bore ``r = r_in + d`` (moved toward the axis by ``squeeze d`` over ``0 < t <= 1``, then held),
the side walls ``z = -w/2`` and ``z = w/2``. The fluid: a ``SolidBodyPressure`` (follower: ``-p J F^-T N`` per
reference area) on the rim faces of ``z <= 0``, its pressure an array over their quadrature points that is ``p``
within ``pressure_arc`` of ``-z`` (seen from the centre, in the reference section) and 0 elsewhere, ramped over
``1 < t <= 2``. The rigid modes: the scene's spring, a body force ``-s(t) E / d^2 u`` per unit volume (consistent,
over the whole cord; the ring's ``2 pi R`` in axisymmetry), ``s = SPRING`` while squeezed and ``SPRING_PRESSURE (2 -
t)`` under pressure: 0 at the end, whose state is the unsprung one.

The load path: squeeze substeps of ``1 / (2 squeeze_steps)``, a step at t = 1 for the spring's jump alone, the
pressure in two substeps (t = 1.5, 2); a ``CutbackPlugin`` subdivides any whose Newton iteration fails (an iterate
that inverts cells included). With more pressure substeps Newton may cycle between two active sets of the side wall
(the two ends of its contact zone in turn), which no cutback passes.

Per reported load step (t = k / squeeze_steps, then 1.5 and 2): the bore's radial force and the side wall's axial
force per unit circumference (axisymmetric: the ring's force over ``2 pi r_bore`` and ``2 pi r_c``, as the
scene; plane strain: per unit length), their peak nodal contact pressures (Cauchy: nodal force over the node's
share of the current contact line, times ``2 pi r``) and contact widths, the fluid's and the walls' axial
resultants (ring totals), the spring's, Newton iterations and time.
"""
from __future__ import annotations

import argparse
import json
import time

import numpy as np

SPRING = 1e-6  # per E / d^2 while squeezed (the oring scene's SPRING)
SPRING_PRESSURE = 1e-2  # per E / d^2 at t = 1, falling linearly to 0 at t = 2 (the scene's SPRING_PRESSURE)
SUBSTEPS_SQUEEZE = 2  # FElupe's substeps per reported squeeze step
SUBSTEPS_PRESSURE = 2  # FElupe's substeps over the pressure phase (t = 1.5, 2: the suite's steps)
VERBOSE = 0  # FElupe's verbosity of the job (2: every Newton iteration)


def wall_profile(y: np.ndarray, x: np.ndarray, nodes: np.ndarray, force: np.ndarray, along: int,
                 axisymmetric: bool) -> tuple[np.ndarray, np.ndarray]:
    """The nodal pressures of a wall on the configuration ``y`` (current: Cauchy; reference: nominal): each node's
    force over its share of the contact line (half its neighbours' segments, the nodes ordered along the wall's
    coordinate ``along`` of ``y``), over ``2 pi r`` in axisymmetry (FElupe's forces are the ring's); with the
    nodes' current coordinates along the wall (of ``x``), sorted."""
    order = np.argsort(x[nodes, along])
    pts, fs = y[nodes][order], force[order]
    seg = np.hypot(*np.diff(pts, axis=0).T)
    tributary = np.zeros(len(pts))
    tributary[:-1] += 0.5 * seg
    tributary[1:] += 0.5 * seg
    weight = 2 * np.pi * pts[:, 1] if axisymmetric else np.ones(len(pts))
    return x[nodes, along][order], np.where(fs > 0, fs / (tributary * weight), 0.0)


class Spring:
    """A FElupe item: the body force ``-factor u`` per unit volume on ``field``'s region (consistent mass-like
    matrix; times ``2 pi R`` if axisymmetric), ``factor`` set by :meth:`update` (a :class:`felupe.Step` ramps it)."""

    def __init__(self, field, axisymmetric: bool):
        import felupe as fem
        from scipy.sparse import coo_matrix, kron

        region = field[0].region
        cells = region.mesh.cells
        h = region.h[..., 0] if region.h.ndim == 3 else region.h  # (nodes per cell, quadrature points)
        dV = region.dV  # (quadrature points, cells)
        if axisymmetric:
            R = np.einsum("aq,ca->qc", h, region.mesh.points[cells, 1])
            dV = dV * 2 * np.pi * R
        local = np.einsum("aq,bq,qc->cab", h, h, dV)
        rows = np.repeat(cells, cells.shape[1], axis=1).ravel()
        cols = np.tile(cells, (1, cells.shape[1])).ravel()
        n = region.mesh.npoints
        mass = coo_matrix((local.ravel(), (rows, cols)), shape=(n, n)).tocsr()
        self.matrix_xy = kron(mass, np.eye(2), format="csr")  # FElupe's dofs: point-major, 2 components
        self.field = field
        self.factor = 0.0
        self.results = fem.mechanics._helpers.Results()
        self.assemble = fem.mechanics._helpers.Assemble(vector=self._vector, matrix=self._matrix)

    def update(self, factor: float) -> None:
        self.factor = float(factor)

    def _vector(self, field=None, **kwargs):
        from scipy.sparse import csr_matrix

        if field is not None:
            self.field = field
        self.results.force = csr_matrix(self.factor * (self.matrix_xy @ self.field[0].values.ravel()).reshape(-1, 1))
        return self.results.force

    def _matrix(self, field=None, **kwargs):
        return self.factor * self.matrix_xy


def run(plane: str, n: int, d: float, r_in: float, E: float, nu: float, squeeze: float, squeeze_steps: int,
        gland_width: float, pressure: float, pressure_arc: float, multiplier: float) -> dict:
    import felupe as fem

    axi = plane == "axisymmetric"
    rc = r_in + 0.5 * d
    w = gland_width
    mu = E / (2 * (1 + nu))
    kappa = E * nu / ((1 + nu) * (1 - 2 * nu)) + 2 * mu / 3
    # FElupe's axisymmetric coordinates are (axial, radial): the mesh is built as (z, r), its cells reordered to
    # keep their orientation after the swap
    disk = fem.mesh.Circle(radius=0.5 * d, centerpoint=[0.0, 0.0], n=n)
    zr = np.column_stack([disk.points[:, 1], rc + disk.points[:, 0]])
    npts = len(zr)
    walls = {"bottom": ([0.0, r_in], [0.0, 1.0]), "bore": ([0.0, r_in + d], [0.0, -1.0]),
             "upstream": ([-0.5 * w, rc], [1.0, 0.0]), "side": ([0.5 * w, rc], [-1.0, 0.0])}
    centre = {name: npts + i for i, name in enumerate(walls)}
    mesh = fem.Mesh(np.vstack([zr] + [[p] for p, _ in walls.values()]), disk.cells[:, ::-1].copy(), "quad")
    region = fem.RegionQuad(mesh)
    kind = fem.FieldAxisymmetric if axi else fem.FieldPlaneStrain
    field = fem.FieldContainer([kind(region, dim=2)])
    u = field[0]
    solid = fem.SolidBodyNearlyIncompressible(fem.NeoHooke(mu=mu), field, bulk=kappa)
    X = mesh.points
    index = np.arange(mesh.npoints)
    rim = np.where(np.isclose(np.hypot(X[:npts, 1] - rc, X[:npts, 0]), 0.5 * d, rtol=1e-8, atol=0))[0]
    contacts = {name: fem.ContactRigidPlane(field, rim, centre[name], normal=normal, items=[solid],
                                            multiplier=multiplier) for name, (_, normal) in walls.items()}
    # the walls' centre points held (name_0: axial, name_1: radial); the bore's radial one ramped
    boundaries = {f"{name}_{i}": fem.Boundary(u, mask=index == centre[name], skip=(i, 1 - i))
                  for name in walls for i in (0, 1)}

    # the fluid: the rim faces of z <= 0, loaded at the quadrature points within pressure_arc of -z
    lower = np.zeros(mesh.npoints, dtype=bool)
    lower[rim[X[rim, 0] <= 1e-12 * d]] = True
    region_p = fem.RegionQuadBoundary(mesh, only_surface=True, mask=lower, ensure_3d=True)
    field_p = fem.FieldContainer([kind(region_p, dim=2)])
    hp = region_p.h[..., 0] if region_p.h.ndim == 3 else region_p.h
    Xq = np.einsum("aq,cad->dqc", hp, X[region_p.mesh.cells])
    arc = (-Xq[0] / np.hypot(Xq[0], Xq[1] - rc) >= np.cos(np.radians(pressure_arc)) - 1e-9).astype(float)
    fluid = fem.SolidBodyPressure(field_p, pressure=0.0 * arc)
    spring = Spring(field, axi)
    spring.update(SPRING * E / d**2)

    # the load path: the reported steps, FElupe's substeps between them (each subdivided by FElupe's cutback if
    # its Newton iteration fails: before the cord touches the side wall only the spring resists the fluid)
    t_squeeze = np.linspace(0.0, 1.0, squeeze_steps * SUBSTEPS_SQUEEZE + 1)  # t = 0: the cutback's start values
    t_pressure = np.linspace(1.0, 2.0, SUBSTEPS_PRESSURE + 1)[1:]
    report = [(k + 1) / squeeze_steps for k in range(squeeze_steps)] + [1.5, 2.0]
    items = [solid, *contacts.values(), fluid, spring]
    # the spring's jump at the start of the pressure phase is a step of its own (at t = 1, not reported): the
    # cutback interpolates each ramped value from the previous substep's, and a jump spread over an increment
    # would leave the cord's first pressure increments held by a weak spring
    paths = [(t_squeeze, t_squeeze), (np.array([1.0]), np.array([1.0 + 1e-12])), (t_pressure, t_pressure)]
    steps = []
    for ts, t_spring in paths:  # every ramped item in every step: the cutback interpolates from the last value
        ramp = {boundaries["bore_1"]: -squeeze * d * np.minimum(ts, 1.0),
                fluid: [pressure * max(t - 1.0, 0.0) * arc for t in ts],
                spring: [E / d**2 * (SPRING if t <= 1.0 else SPRING_PRESSURE * (2.0 - t)) for t in t_spring]}
        steps.append(fem.Step(items=items, ramp=ramp, boundaries=boundaries))
    rows = []
    solves = [0]

    def solver(A, b):
        """scipy's, counting the Newton iterations (every increment's, failed attempts too); an iterate that
        inverted cells (NaN in the matrix: SuperLU's RuntimeError) raised as an error the cutback catches."""
        from scipy.sparse.linalg import spsolve

        solves[0] += 1
        if not np.all(np.isfinite(A.data)):
            raise np.linalg.LinAlgError("the matrix holds NaN (inverted cells)")
        try:
            return spsolve(A, b)
        except RuntimeError as error:
            raise np.linalg.LinAlgError(str(error)) from error

    def record(context, state) -> None:
        t = float(paths[state.stepnumber][0][state.substepnumber])
        if state.stepnumber == 1 or not any(np.isclose(t, r) for r in report):
            return
        x = X + u.values
        # a ContactRigidPlane's vector is its share of the residual, lambda g n: minus the wall's force on the cord
        # (and on the wall's centre point the reaction: the cord's nodes are the first npts)
        forces = {name: -np.asarray(c.results.force.toarray()).reshape(-1, 2) for name, c in contacts.items()}
        row = {"t": t, "squeeze": squeeze * min(t, 1.0), "pressure": pressure * max(t - 1.0, 0.0)}
        r_bore = x[centre["bore"], 1]
        for name, along in (("bore", 0), ("side", 1)):
            half = rim[X[rim, 1] >= rc] if name == "bore" else rim[X[rim, 0] >= 0]  # the wall's half of the rim
            f = forces[name][half] @ np.asarray(walls[name][1])  # the wall's normal force on each node
            _, cauchy = wall_profile(x, x, half, f, along, axi)
            s, nominal = wall_profile(X, x, half, f, along, axi)
            per = 2 * np.pi * (r_bore if name == "bore" else rc) if axi else 1.0
            row.update({f"force_{name}": float(f.sum() / per), f"p0_{name}": float(cauchy.max(initial=0.0)),
                        f"along_{name}": s.tolist(), f"nominal_{name}": nominal.tolist()})
        row["force_upstream"] = float(forces["upstream"][:npts, 0].sum() / (2 * np.pi * rc if axi else 1.0))
        # the pressure's vector as the residual holds it: FElupe's assembly scales it in place by the item's
        # multiplier, -1 (its own vector is the external force)
        fz = -np.asarray(fluid.results.force.toarray()).reshape(-1, 2)[:, 0]
        spring_force = -np.asarray(spring.results.force.toarray()).reshape(-1, 2).sum(axis=0)
        row.update({"fluid_axial_force": float(fz.sum()),
                    "walls_axial_force": float(sum(f[:npts, 0].sum() for f in forces.values())),
                    "spring_force": float(np.hypot(*spring_force)),
                    "penetration": float(max(max(-(x[rim] - x[centre[name]]) @ np.asarray(normal))
                                             for name, (_, normal) in walls.items()) / d),
                    "newton_iterations": solves[0], "converged": True, "time_s": time.perf_counter() - t0})
        rows.append(row)

    t0 = time.perf_counter()
    job = fem.Job(steps, plugins=[record, fem.CutbackPlugin()])
    try:
        job.evaluate(x0=field, tol=1e-9, solver=solver, verbose=VERBOSE)
    except (ArithmeticError, RuntimeError, np.linalg.LinAlgError, fem.tools.NewtonConvergenceError) as error:
        rows.append({"converged": False, "error": f"{type(error).__name__}: {error}"[:300]})
    return {"code": "felupe", "version": fem.__version__, "plane": plane, "n": n, "dofs": int(u.values.size),
            "cells": int(mesh.ncells), "wall_time_s": time.perf_counter() - t0, "rows": rows}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out")
    p.add_argument("--plane", choices=("axisymmetric", "strain"), required=True)
    p.add_argument("--n", type=int, required=True)
    p.add_argument("--d", type=float, default=1.0)
    p.add_argument("--r-in", type=float, default=5.0)
    p.add_argument("--E", type=float, default=1000.0)
    p.add_argument("--nu", type=float, default=0.4999)
    p.add_argument("--squeeze", type=float, default=0.3)
    p.add_argument("--squeeze-steps", type=int, default=3)
    p.add_argument("--gland-width", type=float, default=1.5)
    p.add_argument("--pressure", type=float, default=100.0)
    p.add_argument("--pressure-arc", type=float, default=40.0)
    p.add_argument("--multiplier", type=float, default=100.0)
    a = p.parse_args()
    out = run(a.plane, a.n, a.d, a.r_in, a.E, a.nu, a.squeeze, a.squeeze_steps, a.gland_width, a.pressure,
              a.pressure_arc, a.multiplier)
    with open(a.out, "w") as fh:
        json.dump(out, fh)


if __name__ == "__main__":
    main()
