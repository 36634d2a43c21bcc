"""The pure-Python parts of the FElupe side-by-side run (scripts/felupe/table.py): Lindley's empirical force, the
choice of each code's finest mesh, the comparison and mesh-study tables (the plates and the gland); and the committed
page."""
import math
import re
import sys
from pathlib import Path

import pytest
from history import HISTORY

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts" / "felupe"))

import table  # noqa: E402


def test_lindley_is_the_quoted_relation_per_unit_circumference():
    """``F = pi D d E (1.25 s^1.5 + 50 s^6)`` for the ring of mean diameter D, over its circumference pi D; linear
    in d and E; zero unsqueezed; bad squeeze refused naming it."""
    d, E, s = 2.0, 7.0, 0.2
    D = 30.0
    ring = math.pi * D * d * E * (1.25 * s**1.5 + 50 * s**6)
    assert math.isclose(table.lindley(s, d, E), ring / (math.pi * D), rel_tol=1e-14)
    assert math.isclose(table.lindley(s, 3 * d, 5 * E), 15 * table.lindley(s, d, E), rel_tol=1e-14)
    assert table.lindley(0.0, d, E) == 0.0
    with pytest.raises(ValueError, match="squeeze"):
        table.lindley(1.2, d, E)


def _rows(code, mesh, dofs, forces, status="done"):
    return [{"code": code, "case": "strain", "mesh": mesh, "dofs": dofs, "status": status, "squeeze": s,
             "force": f, "p0": 10 * f, "width": 0.1, "time_s": 1.0, "total_s": 2.0, "newton": 5}
            for s, f in zip(table.SQUEEZES, forces)]


def test_tables_compare_the_finest_meshes_and_state_the_mesh_study():
    n = len(table.SQUEEZES)
    rows = (_rows("FElupe", "n 8", 100, [1.0] * n) + _rows("FElupe", "n 16", 400, [2.0] * n)
            + _rows("fenics_contact", "h d/16", 300, [2.02] * n) + _rows("fenics_contact", "h d/32", 900, [1.0] * n,
                                                                         status="failed"))
    assert [r["mesh"] for r in table.finest(rows, "strain", "FElupe")] == ["n 16"] * n
    # a mesh whose runs failed is not the finest
    assert [r["mesh"] for r in table.finest(rows, "strain", "fenics_contact")] == ["h d/16"] * n
    text, diffs = table.comparison_table(rows, "strain")
    assert [s for s, _ in diffs] == list(table.COMPARED)
    assert all(math.isclose(d, 0.01, rel_tol=1e-12) for _, d in diffs)
    assert text.count("\n") == 1 + n and "| 10% | 2 | 2.02 | +1.00% |" in text
    study = table.mesh_table(rows, "strain")
    assert "| FElupe | n 16 | 400 | 35 | 1 | 2 | 2 (+100.00%) |" in study
    assert "| fenics_contact | h d/32 | failed |" in study


def _gland_rows(code, mesh, dofs, bore, side, status="done"):
    return [{"code": code, "case": "gland", "mesh": mesh, "dofs": dofs, "status": status, "t": t,
             "squeeze": 0.3 * min(t, 1.0), "pressure": 100.0 * max(t - 1.0, 0.0), "force": bore * t,
             "force_side": side * max(t - 1.0, 0.0), "p0": 10.0, "p0_side": 5.0 * max(t - 1.0, 0.0), "width": 0.1,
             "width_side": 0.1, "fluid_axial": 2000.0 * max(t - 1.0, 0.0), "walls_axial": -2000.0 * max(t - 1.0, 0.0),
             "time_s": 1.0, "total_s": 2.0, "newton": 50} for t in table.GLAND_T]


def test_gland_tables_compare_by_load_time_and_state_the_balance():
    """The gland case's rows are found by load time (the squeeze is the same at t = 1, 1.5 and 2): one line per
    step, the bore's and the side wall's force compared where both are loaded; the mesh study's changes; the
    balance of axial forces at the end."""
    rows = (_gland_rows("FElupe", "n 10", 100, 400.0, 60.0) + _gland_rows("FElupe", "n 28", 900, 440.0, 62.0)
            + _gland_rows("fenics_contact", "h d/16", 300, 444.4, 62.62))
    text, diffs = table.gland_table(rows, "gland")
    assert text.count("\n") == 1 + len(table.GLAND_T)
    assert [(name, t) for name, t, _ in diffs] == [("bore", t) for t in table.GLAND_T[:3]] + [
        ("bore", 1.5), ("side", 1.5), ("bore", 2.0), ("side", 2.0)]
    assert all(math.isclose(d, 0.01, rel_tol=1e-9) for _, _, d in diffs)
    assert "| t = 2 | 30% | 0.1 E | 880 | 888.8 | +1.00% | 62 | 62.62 | +1.00% |" in text
    study = table.gland_mesh_table(rows, "gland")
    assert "| FElupe | n 28 | 900 | 50 | 1 | 2 | 440 (+10.00%) | 880 (+10.00%) | 62 (+3.33%) |" in study
    assert table.gland_balance(rows, "gland") == {"FElupe": (2000.0, -2000.0), "fenics_contact": (2000.0, -2000.0)}


def test_committed_felupe_page_states_its_run_and_no_history():
    """docs/bench/felupe.md (scripts/felupe/run.py): the run's command, date and machine, per case the comparison
    table, the mesh study and an existing chart, no development history."""
    page = ROOT / "docs" / "bench" / "felupe.md"
    text = page.read_text()
    assert re.search(r"^Cases [\w, ]+: `python scripts/felupe/run\.py[^`]*` on \d{4}-\d\d-\d\d \d\d:\d\d UTC, .+, "
                     r"\d+ cores, [\d.]+ GB", text, flags=re.M), text[:400]
    assert not HISTORY.search(text), HISTORY.search(text)
    images = re.findall(r"\]\(([^)]+\.png)\)", text)
    assert images and all((page.parent / image).exists() for image in images)
    assert (text.count("| squeeze | force FElupe | force here |")
            + text.count("| step | squeeze | pressure | bore force FElupe |")) == len(images)
    assert text.count("| code | mesh | dofs | Newton |") == len(images)
