"""The page of the side-by-side run (scripts/peer/run.py): docs/bench/peer.md, one table and one
accuracy-against-time chart (peer_<case>.png) per case, headed by the machine and date of the run.

    python scripts/peer/page.py results/peer/rows.json docs/bench
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TITLES = {"hertz2d": "Two-body Hertz, 2D", "hertz3d": "Two-body Hertz, 3D",
          "cylinders": "Cattaneo-Mindlin friction cylinders, 2D", "wedges": "Sliding wedges, 2D"}
SETUP = {
    "hertz2d": "Cylinder (R 8) on a block, both E 200, nu 0.3, load 10 per unit length. Peer: its "
               "`demo_hertzian_contact.py --problem 2` (half disk on a 20 x 20 block, quadrilaterals, the load a "
               "traction on the diameter in 4 steps, unbiased Nitsche gamma = 100 E, GMRES + GAMG; its "
               "`--problem 1` stops at v0.9.0: its mesh call passes a file name where the function takes a gmsh "
               "model), mesh `--res` (contact h = res / 2). "
               "Here: the `hertz` scene's two-body case (quarter disk on a 32 x 16 block, contact h = R / 400 "
               "halved per `--refinement`, MUMPS). Error: peak pressure p0 against Hertz's.",
    "hertz3d": "Sphere (R 8) on a block, both E 200, nu 0.3, load 5. Peer: `demo_hertzian_contact.py "
               "--3D` (half sphere on a 20^3 box, tetrahedra, a volume force in 4 steps, of the density that would "
               "put its load 10 on a whole sphere: 5 on the half sphere, integrated from its mesh; h = res near the "
               "contact; its Dirichlet vertices flattened, which dolfinx 0.9 needs). Here: the `sphere` scene's "
               "two-body octant, approach 0.0526 (Hertz's for load 5), "
               "`--level`; nitsche with GMRES + GAMG, coulomb (exact, condensed) with MUMPS. Error: peak pressure p0 "
               "against Hertz's at each code's own force (here from the contact pressure's moments).",
    "cylinders": "Two cylinders (R 8), E 200, nu 0.3, mu 0.3, pressed then sheared. Peer: "
                 "`demo_friction_cylinders.py` (quarter disks, displacement driven: 4 pressing steps, 96 "
                 "shearing steps, Coulomb Nitsche gamma = 10 E). Here: the `mindlin` scene (force driven, "
                 "Q / (mu P) = 0.2, 0.5, 0.8); nitsche in finite sliding (current pairs and normals, the default) "
                 "and nitsche-small in small sliding (`--sliding small`: reference pairs and normals, the "
                 "kinematics of Mindlin's linear theory and of the exact coulomb). Error: the stick zone's "
                 "half-width c against Mindlin's "
                 "a sqrt(1 - Q / (mu P)) (peer: at its last step; here: the worst of the three ratios).",
    "wedges": "A block pushed up an incline, mu 0.5, alpha = atan 0.1, E 200, nu 0.3. Peer: "
              "`demo_sliding_wedges.py` (one load step, Coulomb Nitsche gamma = 10 E, skew-symmetric). Here: "
              "the `wedges` scene. Error: horizontal over vertical force against (mu + tan alpha) / "
              "(1 - mu tan alpha).",
}


def _fmt(x, digits=3):
    if x is None:
        return "-"
    if isinstance(x, float):
        return f"{x:.{digits}g}"
    return str(x)


def _label(r: dict) -> str:
    return "dolfinx_contact (peer)" if r["code"] == "dolfinx_contact" else f"fenics_contact {r['method']}"


def _ratios(rows: list[dict]) -> list[str]:
    """Per peer run: the fastest run of this suite with equal or better error, and the time ratio."""
    lines = []
    ours = [r for r in rows if r["code"] == "fenics_contact"]
    for p in (r for r in rows if r["code"] == "dolfinx_contact"):
        better = [r for r in ours if r["error"] <= p["error"]]
        if not better:
            lines.append(f"peer at res {p['level']} (error {p['error']:.3g}, {p['wall_time_s']:.3g} s): no run of "
                         "this suite as accurate")
            continue
        best = min(better, key=lambda r: r["wall_time_s"])
        mesh = "" if best["level"] is None else f" level {best['level']}"
        lines.append(f"peer at res {p['level']} (error {p['error']:.3g}, {p['wall_time_s']:.3g} s): "
                     f"{best['method']}{mesh} (error {best['error']:.3g}, {best['wall_time_s']:.3g} s); time of the "
                     f"peer over this suite's: **{p['wall_time_s'] / best['wall_time_s']:.3g}**")
    return lines


def write_page(rows_json: Path, docs: Path) -> Path:
    data = json.loads(Path(rows_json).read_text())
    runs, rows = data["runs"], data["rows"]
    Path(docs).mkdir(parents=True, exist_ok=True)
    lines = ["# The peer side by side: dolfinx_contact and fenics_contact on the same cases", ""]
    for run in runs:
        m = run["machine"]
        lines += ["Cases {cases}: `{cmd}` on {date}, {cpu}, {cores} cores, {mem} GB, {system}, load average {load} "
                  "at the start (other jobs shared the cores: times are noisy); both codes in the same Debian 13 "
                  "root (dolfinx {dolfinx}), serial, the peer at {peer}.".format(
                      cases=", ".join(run["cases"]), cmd=run["command"], date=run["date"], cpu=m["cpu"],
                      cores=m["cores"], mem=m["memory_gb"], system=m["system"], load=run["load_average"],
                      dolfinx=", ".join(run["dolfinx"]) or "?", peer=run["peer"]), ""]
    lines += ["How to run it: [benchmarks](../benchmarks.md) (`make peer`). "
             "Columns: `dofs` displacement unknowns; `Newton` Newton iterations of all steps; `solves` linear "
             "solves; `Krylov` Krylov iterations (iterative solvers; a direct solve counts 0 or 1); `time` the "
             "solver's wall time (s; meshing, form compilation and output excluded); `total` with set-up; "
             "`value` the case's figure, `error` its relative distance from the closed form. A failed run "
             "says so.", ""]
    for case in TITLES:
        crow = [r for r in rows if r["case"] == case]
        if not crow:
            continue
        lines += [f"## {TITLES[case]}", "", SETUP[case], "",
                  "| code | method | mesh | dofs | Newton | solves | Krylov | time (s) | total (s) | value | "
                  "reference | error |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in crow:
            if r["status"] != "done":
                log = [line.strip() for line in r.get("log", "").splitlines() if line.strip()]
                reason = [line for line in log if "Error" in line][-1:] or log[-1:] or ["?"]
                lines.append(f"| {r['code']} | {r['method']} | {_fmt(r['level'])} | failed: "
                             f"{reason[0][:120].replace('|', '/')} |||||||||")
                continue
            lines.append("| " + " | ".join([r["code"], r["method"], _fmt(r["level"]), str(r["dofs"]),
                                            str(r["newton_iterations"]), str(r["linear_solves"]),
                                            _fmt(r.get("krylov_iterations")), _fmt(r["wall_time_s"]),
                                            _fmt(r.get("total_time_s")), _fmt(r.get("value"), 5),
                                            _fmt(r.get("reference"), 5),
                                            _fmt(r["error"]) + (" (its check failed)" if r.get("check") else "")])
                         + " |")
        done = [r for r in crow if r["status"] == "done"]
        if done:
            fig, ax = plt.subplots(figsize=(5.5, 4))
            for label in dict.fromkeys(_label(r) for r in done):
                pts = sorted((r["wall_time_s"], r["error"]) for r in done if _label(r) == label)
                ax.loglog([p[0] for p in pts], [max(p[1], 1e-6) for p in pts], "o-", label=label)
            ax.set_xlabel("solver wall time (s)")
            ax.set_ylabel("relative error against the closed form")
            ax.set_title(TITLES[case], fontsize=10)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=8)
            fig.tight_layout()
            fig.savefig(docs / f"peer_{case}.png", dpi=110)
            plt.close(fig)
            ratios = _ratios(done)
            lines += ["", f"![{TITLES[case]}: error against solver time](peer_{case}.png)", "",
                      *(["Time at equal or better accuracy:", "", *[f"- {s}" for s in ratios]] if ratios else
                        ["No run of the peer finished: no ratio."])]
        lines.append("")
    lines += ["## Summary", "", "Per case, the peer's most accurate run against the fastest run of this suite with "
              "equal or better error (same run, same machine):", ""]
    for case in TITLES:
        done = [r for r in rows if r["case"] == case and r["status"] == "done"]
        peer = [r for r in done if r["code"] == "dolfinx_contact"]
        if peer:
            best = min(peer, key=lambda r: r["error"])
            ours = [r for r in done if r["code"] != "dolfinx_contact"]
            lines.append(f"- {TITLES[case]}: " + _ratios([best, *ours])[0])
    lines.append("")
    path = docs / "peer.md"
    path.write_text("\n".join(lines))
    return path


if __name__ == "__main__":
    if len(sys.argv) != 3:
        print("usage: page.py ROWS.json DOCS_DIR", file=sys.stderr)
        sys.exit(2)
    print(write_page(Path(sys.argv[1]), Path(sys.argv[2])))
