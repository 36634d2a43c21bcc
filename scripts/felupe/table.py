"""What the FElupe side-by-side run (scripts/felupe/run.py) and its page (scripts/felupe/page.py) share: the cases,
the material, the squeezes, the gland's load, Lindley's empirical force, and the tables made from the run's rows (pure
Python)."""
from __future__ import annotations

import math

# The O-ring cord of the suite's ``oring`` scene: d 1 on the groove bottom r = 5 d; neo-Hookean, E 1000,
# nu 0.4999 (shear modulus E / (2 (1 + nu)) = 333.36, bulk modulus kappa = lambda + 2 mu / 3 = 1.67e6).
MATERIAL = {"d": 1.0, "r_in": 5.0, "E": 1000.0, "nu": 0.4999}
SQUEEZES = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35]
COMPARED = (0.1, 0.2, 0.3)  # the squeezes of the acceptance (2 %)
TOLERANCE = 0.02
CASES = {"strain": {"plane": "strain", "title": "Cord between two plates, plane strain"},
         "axisymmetric": {"plane": "axisymmetric", "title": "Ring between two coaxial cylinders, axisymmetric"},
         "gland": {"plane": "axisymmetric", "gland": True,
                   "title": "O-ring in its gland, squeezed then pressurised, axisymmetric"}}
# The gland case: the oring scene's defaults (fenics_contact/app/scenes/oring.py): the gland 1.5 d wide, the squeeze
# 30 % of d in three steps (t = 1/3, 2/3, 1), then the fluid pressure 0.1 E on the arc within 40 degrees of -z in two
# (t = 1.5, 2; the rigid-mode spring gone at t = 2)
GLAND = {"gland_width": 1.5, "squeeze": 0.3, "steps": 3, "pressure": 0.1, "pressure_arc": 40.0, "pressure_steps": 2}
GLAND_T = (1 / 3, 2 / 3, 1.0, 1.5, 2.0)


def lindley(squeeze: float, d: float, E: float) -> float:
    """Lindley's empirical force per unit circumference of an O-ring (per unit length of cord) squeezed by the
    fraction ``squeeze`` of its cord diameter ``d``: ``F / (pi D) = d E (1.25 s^1.5 + 50 s^6)``, from ``F = pi D d E
    (1.25 s^1.5 + 50 s^6)`` for the whole ring of mean diameter ``D`` (P. B. Lindley, 1967, as quoted in the O-ring
    literature; a fit to ring tests, not a closed form). ``E`` Young's modulus
    (stress); returns a force per length."""
    if not 0 <= squeeze < 1:
        raise ValueError(f"squeeze must be in [0, 1), got {squeeze!r}")
    return d * E * (1.25 * squeeze**1.5 + 50 * squeeze**6)


def _load(row: dict) -> float:
    """A row's place on the load path: its time ``t`` (the gland case) or its squeeze."""
    return row.get("t", row.get("squeeze", 0.0))


def finest(rows: list[dict], case: str, code: str) -> list[dict]:
    """The rows of ``code`` on its finest mesh that ran in ``case`` (the mesh whose rows are all done), by
    squeeze (the gland case: by load time)."""
    done = [r for r in rows if r["case"] == case and r["code"] == code and r["status"] == "done"]
    meshes = sorted({r["mesh"] for r in done}, key=lambda m: max(r["dofs"] for r in done if r["mesh"] == m))
    for mesh in reversed(meshes):
        mine = sorted((r for r in done if r["mesh"] == mesh), key=_load)
        if mine:
            return mine
    return []


def meshes(rows: list[dict], case: str, code: str) -> list[list[dict]]:
    """The rows of ``code`` in ``case`` per mesh, coarsest first (a mesh's rows by squeeze, or load time)."""
    mine = [r for r in rows if r["case"] == case and r["code"] == code]
    names = sorted({r["mesh"] for r in mine}, key=lambda m: max([r.get("dofs", 0) for r in mine if r["mesh"] == m]))
    return [sorted((r for r in mine if r["mesh"] == m), key=_load) for m in names]


def at(rows: list[dict], value: float, key: str = "squeeze") -> dict | None:
    """The row whose ``key`` (squeeze, or load time ``t``) is ``value`` (to 1e-9), or None."""
    hit = [r for r in rows if key in r and math.isclose(r[key], value, rel_tol=1e-9)]
    return hit[0] if hit else None


def _g(x, digits: int = 4) -> str:
    return "-" if x is None or (isinstance(x, float) and not math.isfinite(x)) else f"{x:.{digits}g}"


def comparison_table(rows: list[dict], case: str) -> tuple[str, list[tuple[float, float]]]:
    """The Markdown table of both codes' finest meshes side by side, one line per squeeze, and the force's relative
    difference (this suite's over FElupe's, less 1) at each squeeze of :data:`COMPARED`."""
    fe, ours = finest(rows, case, "FElupe"), finest(rows, case, "fenics_contact")
    m = MATERIAL
    lines = ["| squeeze | force FElupe | force here | difference | p0 FElupe | p0 here | width FElupe | width here "
             "| Lindley |", "|---|---|---|---|---|---|---|---|---|"]
    diffs = []
    for s in SQUEEZES:
        a, b = at(fe, s), at(ours, s)
        diff = b["force"] / a["force"] - 1 if a and b else None
        if diff is not None and any(math.isclose(s, c) for c in COMPARED):
            diffs.append((s, diff))
        lines.append(f"| {s:.0%} | {_g(a and a['force'])} | {_g(b and b['force'])} | "
                     f"{'-' if diff is None else f'{diff:+.2%}'} | {_g(a and a['p0'])} | {_g(b and b['p0'])} | "
                     f"{_g(a and a['width'], 3)} | {_g(b and b['width'], 3)} | {_g(lindley(s, m['d'], m['E']))} |")
    return "\n".join(lines), diffs


def mesh_table(rows: list[dict], case: str) -> str:
    """The Markdown table of the mesh study: per code and mesh its dofs, Newton iterations (all steps), solver
    time, and the force at each squeeze of :data:`COMPARED` with its change from the next coarser mesh."""
    head = " | ".join(f"force {s:.0%} (change)" for s in COMPARED)
    lines = [f"| code | mesh | dofs | Newton | time (s) | total (s) | {head} |",
             "|---|---|---|---|---|---|" + "---|" * len(COMPARED)]
    for code in ("FElupe", "fenics_contact"):
        previous = None
        for mesh in meshes(rows, case, code):
            first = mesh[0]
            if any(r["status"] != "done" for r in mesh):
                lines.append(f"| {code} | {first['mesh']} | failed |" + " |" * (3 + len(COMPARED)))
                previous = None
                continue
            cells = []
            for s in COMPARED:
                r, p = at(mesh, s), previous and at(previous, s)
                change = f" ({r['force'] / p['force'] - 1:+.2%})" if r and p else ""
                cells.append(f"{_g(r and r['force'])}{change}")
            newton = sum(r["newton"] for r in mesh) if code == "FElupe" else first["newton"]
            lines.append(f"| {code} | {first['mesh']} | {first['dofs']} | {newton} | {_g(first['time_s'], 3)} | "
                         f"{_g(first['total_s'], 3)} | " + " | ".join(cells) + " |")
            previous = mesh
    return "\n".join(lines)


def _diff(a: dict | None, b: dict | None, key: str) -> float | None:
    """``b[key] / a[key] - 1`` (this suite's over FElupe's), None if either is missing or FElupe's is 0."""
    return b[key] / a[key] - 1 if a and b and a.get(key) else None


def _pct(x: float | None) -> str:
    return "-" if x is None else f"{x:+.2%}"


def gland_table(rows: list[dict], case: str) -> tuple[str, list[tuple[str, float, float]]]:
    """The Markdown table of the gland case, both codes' finest meshes side by side, one line per load step of
    :data:`GLAND_T`: the bore's and the side wall's force, their differences, the peak pressures; and the forces'
    relative differences (this suite's over FElupe's, less 1) as ``(figure, t, difference)``."""
    fe, ours = finest(rows, case, "FElupe"), finest(rows, case, "fenics_contact")
    lines = ["| step | squeeze | pressure | bore force FElupe | bore force here | difference | side force FElupe | "
             "side force here | difference | p0 bore FElupe | p0 bore here | p0 side FElupe | p0 side here |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    diffs = []
    for t in GLAND_T:
        a, b = at(fe, t, "t"), at(ours, t, "t")
        bore, side = _diff(a, b, "force"), _diff(a, b, "force_side")
        diffs += [(name, t, d) for name, d in (("bore", bore), ("side", side)) if d is not None]
        r = a or b
        state = (f"{r['squeeze']:.0%} | {r['pressure'] / MATERIAL['E']:.3g} E" if r else "- | -")
        lines.append(f"| t = {t:.3g} | {state} | {_g(a and a['force'])} | {_g(b and b['force'])} | {_pct(bore)} | "
                     f"{_g(a and a['force_side'])} | {_g(b and b['force_side'])} | {_pct(side)} | "
                     f"{_g(a and a['p0'])} | {_g(b and b['p0'])} | {_g(a and a['p0_side'])} | "
                     f"{_g(b and b['p0_side'])} |")
    return "\n".join(lines), diffs


def gland_balance(rows: list[dict], case: str) -> dict[str, tuple[float, float]]:
    """Per code (its finest mesh), the fluid's and the walls' axial force on the cord at the end of the pressure
    phase (ring totals; plane strain: per unit length): they balance, the rigid-mode spring being gone."""
    out = {}
    for code in ("FElupe", "fenics_contact"):
        r = at(finest(rows, case, code), GLAND_T[-1], "t")
        if r:
            out[code] = (r["fluid_axial"], r["walls_axial"])
    return out


def gland_mesh_table(rows: list[dict], case: str) -> str:
    """The Markdown table of the gland case's mesh study: per code and mesh its dofs, Newton iterations, solver
    time, the bore's force after the squeeze and after the pressure and the side wall's after the pressure, each
    with its change from the next coarser mesh."""
    cells_of = (("force", 1.0), ("force", 2.0), ("force_side", 2.0))
    lines = ["| code | mesh | dofs | Newton | time (s) | total (s) | bore force t = 1 (change) | bore force t = 2 "
             "(change) | side force t = 2 (change) |", "|---|---|---|---|---|---|---|---|---|"]
    for code in ("FElupe", "fenics_contact"):
        previous = None
        for mesh in meshes(rows, case, code):
            first = mesh[0]
            if any(r["status"] != "done" for r in mesh):
                lines.append(f"| {code} | {first['mesh']} | failed |" + " |" * (3 + len(cells_of)))
                previous = None
                continue
            cells = []
            for key, t in cells_of:
                r, p = at(mesh, t, "t"), previous and at(previous, t, "t")
                change = f" ({r[key] / p[key] - 1:+.2%})" if r and p and p[key] else ""
                cells.append(f"{_g(r and r[key])}{change}")
            lines.append(f"| {code} | {first['mesh']} | {first['dofs']} | {first['newton']} | "
                         f"{_g(first['time_s'], 3)} | {_g(first['total_s'], 3)} | " + " | ".join(cells) + " |")
            previous = mesh
    return "\n".join(lines)
