"""The page of the FElupe side-by-side run (scripts/felupe/run.py): docs/bench/felupe.md, per case one table of
both codes' finest meshes, one mesh-study table and one chart (felupe_<case>.png: force, peak contact pressure and
contact width against squeeze, Lindley's empirical force as a line; the gland case: the bore's and the side wall's
force and peak pressure against the load time), headed by the machine and date of the run.

    python scripts/felupe/page.py results/felupe/rows.json docs/bench
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import table  # noqa: E402
from table import CASES, COMPARED, GLAND, GLAND_T, MATERIAL, TOLERANCE, at, finest, lindley  # noqa: E402

INTRO = """\
An independent code on the same problems: [FElupe](https://github.com/adtzlr/felupe) (A. Dutzler, pure Python,
from the package index), with its own elements, incompressibility treatment and contact, against this suite's
`oring` scene. Both model an O-ring cord of diameter d = 1 on a groove bottom at r = 5 d, squeezed between two
rigid frictionless plates (the groove bottom fixed, the bore moved toward it; axisymmetric: two coaxial cylinders,
the ring's hoop stiffness included) by 5 to 35 % of d in seven steps, the rubber neo-Hookean, E = 1000, nu = 0.4999
(shear modulus 333.36, bulk modulus 1.67e6: the energy `mu/2 (I1_bar - 3) + kappa/2 (J - 1)^2` in both). The
gland case (its own section below) puts the same cord in the scene's gland, squeezes it and pressurises it.

- **FElupe**: the half cord `z >= 0` (its symmetry plane held), FElupe's quadrilateral circle mesh (`n` points on
  a 45-degree edge, 8 (n - 1) segments round the cord), bilinear displacement with the three-field mean-dilatation
  formulation (`SolidBodyNearlyIncompressible`: cell-wise constant pressure and volume ratio), two
  `ContactRigidPlane` (node-to-plane penalty, its multiplier 100 times the solid's mean diagonal stiffness at the
  contact nodes: penetration below 4e-7 d), Newton to 1e-9; plane strain with the cord's centre held at `u_r = 0`
  and both plates moving by half the squeeze (the frictionless plates leave the cord's translation free: the
  symmetric equivalent), axisymmetric as below. The peak pressure: the largest nodal force over the node's share of
  the current contact line (times 2 pi r); the width: the same edge extrapolation as this suite's, applied to the
  nodal pressures per reference length.
- **fenics_contact**: the `oring` scene with a gland three cords wide (its side walls never touched) and no
  fluid pressure: the whole cord, gmsh triangles of size h on its surface, P2-P1 Taylor-Hood (`neohookean-mixed`),
  Gauss-point contact against analytic half-planes, augmented Lagrangian (`auglag`, augmented until the gap
  changes by less than 1e-6 of the mesh's size: the exact-contact limit), MUMPS; the peak is the Cauchy contact
  stress, the width the loaded zone of the nominal pressure with its ends extrapolated as Hertz's.

Force: per unit circumference (axisymmetric: the ring's radial force on the bore over 2 pi r_bore) or per unit
length (plane strain). **Lindley's relation** `F = pi D d E (1.25 s^1.5 + 50 s^6)` (P. B. Lindley, 1967, as quoted
in the O-ring literature; its text could not be read here), per unit circumference `d E (1.25 s^1.5 + 50 s^6)`,
is an empirical fit to ring tests, drawn as a line and
not used as a reference. Columns: `dofs` unknowns (FElupe: the displacement of its half cord, its cell-wise
pressure and volume ratio condensed; here the whole cord's displacement and pressure); `Newton` Newton iterations of
all steps (here with the augmentations and any cut-back steps); `time` the solver's wall time (s); `total` the
process's; p0 the peak contact pressure (Cauchy), width the contact width, both at the bore.

Where the codes differ more than in the force: the peak pressure and the width are read off each code's own
discrete contact (FElupe: nodal forces over each node's share of the contact line, the consistent nodal forces of a
bilinear element lumped; here the pressure recovered at the P2 vertices from the Gauss points), so they carry the
resolution of the contact zone: a few nodes across it at low squeeze. The width's ends are extrapolated from those
few points; it is the figure that differs most, and most at 5 % squeeze, where the zone spans the fewest nodes.
"""


def _chart(rows: list[dict], case: str, path: Path) -> None:
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    styles = {"FElupe": ("tab:blue", "s"), "fenics_contact": ("tab:red", "o")}
    for code, (color, marker) in styles.items():
        levels = [m for m in table.meshes(rows, case, code) if all(r["status"] == "done" for r in m)]
        for i, mesh in enumerate(levels):
            last = i == len(levels) - 1
            s = [r["squeeze"] for r in mesh]
            axes[0].plot(s, [r["force"] for r in mesh], marker=marker if last else None, color=color,
                         alpha=1.0 if last else 0.35, lw=1.6 if last else 0.8,
                         label=f"{code} {mesh[0]['mesh']}" if last else None)
        best = finest(rows, case, code)
        s = [r["squeeze"] for r in best]
        label = f"{code} {best[0]['mesh']}" if best else code
        axes[1].plot(s, [r["p0"] for r in best], marker=marker, color=color, label=label)
        axes[2].plot(s, [r["width"] for r in best], marker=marker, color=color, label=label)
    s = [i / 200 for i in range(0, 81)]
    axes[0].plot(s, [lindley(x, MATERIAL["d"], MATERIAL["E"]) for x in s], "k--", lw=1,
                 label="Lindley 1967 (empirical)")
    for ax, what in zip(axes, ("force per unit circumference", "peak contact pressure", "contact width")):
        ax.set(xlabel="squeeze s (of d)", ylabel=what)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_title(f"{CASES[case]['title']} (coarser meshes faint)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _spread(rows: list[dict], case: str) -> str:
    """The largest relative differences of the peak pressure and the width at the compared squeezes."""
    fe, ours = finest(rows, case, "FElupe"), finest(rows, case, "fenics_contact")
    out = []
    for key, name in (("p0", "peak pressure"), ("width", "contact width")):
        d = [b[key] / a[key] - 1 for s in COMPARED if (a := at(fe, s)) and (b := at(ours, s)) and a[key] > 0]
        if d:
            out.append(f"{name} {min(d):+.1%} to {max(d):+.1%}")
        else:
            out.append(f"{name} not compared")
    return "At the same squeezes: " + ", ".join(out) + "."


GLAND_INTRO = """\
The cord of the cases above in the `oring` scene's rigid rectangular gland, with its default load (axisymmetric):
the groove bottom r = 5 d (fixed), the bore r = 6 d moved toward the axis by 30 % of d in three steps (t = 1/3, 2/3,
1), the side walls z = -0.75 d and z = +0.75 d (the gland {width:g} d wide), then the fluid pressure {p:g} E in two
steps (t = 1.5, 2) on the arc of the cord's surface within {arc:g} degrees of -z (seen from the cord's centre in the
reference section), a follower load (normal to the current surface, per current area); it pushes the cord onto the
side wall z = +0.75 d. Both codes model the whole cord (the pressure breaks the
symmetry), four frictionless rigid walls against every surface point, and the same stabilisation of the rigid
motions the frictionless gland leaves free before the cord touches the side wall: the scene's spring, a body force
`-s(t) E / d^2 u` per unit volume over the whole cord, s = 1e-6 while squeezed and 1e-2 (2 - t) under pressure, 0 at
the end: the last state is the unsprung one.

- **FElupe** (scripts/felupe/felupe_gland.py): the whole circle mesh (`n - 1` a multiple of 9: the arc's ends are
  nodes), four `ContactRigidPlane` (multiplier 100, every rim node against every wall), the fluid a
  `SolidBodyPressure` on the rim faces of z <= 0 whose pressure is an array over their quadrature points, p within the
  arc and 0 outside (the arc fixed in the reference section, as the suite's), the spring an item of its own (its
  consistent matrix, `2 pi R` weighted), the bore's motion, the pressure and the spring ramped by a `Step`: squeeze
  substeps of 5 %, the pressure in the suite's two steps, each subdivided by FElupe's `CutbackPlugin` where Newton
  fails (the first, where the cord slides onto the side wall); the spring's jump from 1e-6 to 1e-2 at t = 1 is a
  step of its own (the cutback interpolates each ramped value from the previous substep's). `dofs`: the whole
  cord's displacement.
- **fenics_contact**: `demos/oring.py` with the scene's gland and load (`--gland-width 1.5 --pressure 100`), the
  penalty at K = 1000 E / h (ten times the scene's default; its penetration p / K falls with h), where the augmented
  Lagrangian's Newton iteration cycles between two active sets of the side wall (from h = d/32).

Forces per unit circumference: the bore's radial force over 2 pi r_bore, the side wall's axial force over 2 pi r_c
(r_c = 5.5 d, the cord's centre: the scene's figure). p0: the peak contact pressure (Cauchy) on each wall. At t =
1.5 the spring still carries part of the fluid's axial force (the same spring in both codes). The balance: the
fluid's axial force on the cord and the walls' at t = 2 (ring totals).
"""


def _gland_chart(rows: list[dict], case: str, path: Path) -> None:
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    styles = {"FElupe": ("tab:blue", "s"), "fenics_contact": ("tab:red", "o")}
    for code, (color, marker) in styles.items():
        levels = [m for m in table.meshes(rows, case, code) if all(r["status"] == "done" for r in m)]
        for i, mesh in enumerate(levels):
            last = i == len(levels) - 1
            t = [r["t"] for r in mesh]
            for ax, key in zip(axes[:2], ("force", "force_side")):
                ax.plot(t, [r[key] for r in mesh], marker=marker if last else None, color=color,
                        alpha=1.0 if last else 0.35, lw=1.6 if last else 0.8,
                        label=f"{code} {mesh[0]['mesh']}" if last else None)
        best = finest(rows, case, code)
        t = [r["t"] for r in best]
        name = f"{code} {best[0]['mesh']}" if best else code
        axes[2].plot(t, [r["p0"] for r in best], marker=marker, color=color, label=f"bore, {name}")
        axes[2].plot(t, [r["p0_side"] for r in best], marker=marker, color=color, ls="--", mfc="none",
                     label=f"side wall, {name}")
    for ax, what in zip(axes, ("bore force per unit circumference", "side wall force per unit circumference",
                               "peak contact pressure")):
        ax.set(xlabel="load time t (squeeze to t = 1, then pressure)", ylabel=what)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"{CASES[case]['title']} (coarser meshes faint)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _gland_section(rows: list[dict], case: str, docs: Path, intro: bool) -> list[str]:
    """The section of a gland case: the cases' description (``intro``: before the first), the comparison, the
    balance of axial forces, the mesh study and the chart."""
    comparison, diffs = table.gland_table(rows, case)
    worst = max((abs(d) for _, _, d in diffs), default=float("nan"))
    listed = ", ".join(f"{name} {d:+.2%} at t = {t:.3g}" for name, t, d in diffs)
    verdict = (f"the forces agree within {TOLERANCE:.0%} at every step" if worst <= TOLERANCE else
               f"the forces differ by more than {TOLERANCE:.0%} somewhere") + f": {listed} (this suite over FElupe)."
    balance = "; ".join(f"{code}: fluid {fluid:.5g}, walls {walls:.5g} (sum {(fluid + walls) / fluid:+.1e} of the "
                        "fluid's)" for code, (fluid, walls) in table.gland_balance(rows, case).items())
    _gland_chart(rows, case, docs / f"felupe_{case}.png")
    text = GLAND_INTRO.format(width=GLAND["gland_width"], p=GLAND["pressure"], arc=GLAND["pressure_arc"])
    per = "ring totals" if CASES[case]["plane"] == "axisymmetric" else "per unit length"
    return [f"## {CASES[case]['title']}\n", *([text] if intro else []),
            f"Both codes' finest meshes; {verdict} Axial balance at t = {GLAND_T[-1]:g} ({per}): {balance}.\n",
            comparison + "\n",
            "Mesh study (in brackets the change from the next coarser mesh):\n",
            table.gland_mesh_table(rows, case) + "\n",
            f"![{CASES[case]['title']}: forces and peak pressures against the load](felupe_{case}.png)\n"]


def write_page(rows_json: Path, docs: Path) -> Path:
    """Write ``docs``/felupe.md and its charts from a run's ``rows.json``; return the page's path."""
    data = json.loads(Path(rows_json).read_text())
    runs, rows = data["runs"], data["rows"]
    text = ["# FElupe side by side: an O-ring cord between two plates and in its gland\n"]
    for rec in runs:
        m = rec["machine"]
        where = ", ".join(str(x) for x in (m.get("cpu"), f"{m.get('cores')} cores", f"{m.get('memory_gb')} GB",
                                          m.get("system")) if x)
        text.append(f"Cases {', '.join(rec['cases'])}: `{rec['command']}` on {rec['date']}, {where}, load average "
                    f"{rec['load_average']} at the start (other jobs shared the cores: times are noisy); FElupe "
                    f"{rec['felupe']} in its own venv, this suite on dolfinx under the system Python, every job "
                    "serial.\n")
    text += ["How to run it: [benchmarks](../benchmarks.md) (`make felupe`).\n", INTRO]
    cases = [c for c in CASES if any(c in rec["cases"] for rec in runs)]
    docs.mkdir(parents=True, exist_ok=True)
    for case in cases:
        if CASES[case].get("gland"):
            text += _gland_section(rows, case, docs, intro=not any(CASES[c].get("gland") for c in
                                                                   cases[:cases.index(case)]))
            continue
        comparison, diffs = table.comparison_table(rows, case)
        worst = max((abs(d) for _, d in diffs), default=float("nan"))
        verdict = (f"the force agrees within {TOLERANCE:.0%} at " if worst <= TOLERANCE else
                   f"the force differs by more than {TOLERANCE:.0%} somewhere among ") + \
            ", ".join(f"{s:.0%}" for s in COMPARED) + " squeeze: " + \
            ", ".join(f"{d:+.2%}" for _, d in diffs) + " (this suite over FElupe, finest meshes)."
        _chart(rows, case, docs / f"felupe_{case}.png")
        text += [f"## {CASES[case]['title']}\n",
                 f"Both codes' finest meshes; {verdict} {_spread(rows, case)}\n", comparison + "\n",
                 "Mesh study (force at 10, 20, 30 % squeeze; in brackets its change from the next coarser mesh):\n",
                 table.mesh_table(rows, case) + "\n",
                 f"![{CASES[case]['title']}: force, peak pressure and width against squeeze](felupe_{case}.png)\n"]
    failed = [r for r in rows if r["status"] != "done"]
    if failed:
        text.append("Failed jobs: " + "; ".join(f"{r['code']} {r['case']} {r['mesh']}" for r in failed) + ".\n")
    path = docs / "felupe.md"
    path.write_text("\n".join(text))
    return path


if __name__ == "__main__":
    write_page(Path(sys.argv[1]), Path(sys.argv[2]))
    print(f"wrote {Path(sys.argv[2]) / 'felupe.md'}")
