"""The speed-against-accuracy harness: the Pareto front, and a two-run sweep on the block."""
import csv
import math

import numpy as np
import pytest
from mpi4py import MPI

from fenics_contact import methods
from fenics_contact.app import bench, bench_run


def test_pareto_front_hand_made():
    #            0    1    2     3    4    5    6      7
    times = [1.0, 2.0, 0.5, 3.0, 2.0, 4.0, np.nan, 0.5]
    errors = [1e-2, 1e-3, 5e-2, 1e-3, 2e-3, 1e-6, 1e-9, 5e-2]
    # 2 (fastest), 0 (better), 1 (better; 4 same time but worse), 3 is not better than 1, 5 best;
    # 6 has no time; 7 duplicates 2 (the first is kept)
    assert bench.pareto_front(times, errors).tolist() == [2, 0, 1, 5]
    assert bench.pareto_front([], []).tolist() == []
    assert bench.pareto_front([3.0, 2.0, 1.0], [1.0, 1.0, 1.0]).tolist() == [2]


def test_sweep_block(tmp_path):
    # every rank runs its own serial demos into its own folder
    out = tmp_path / f"rank{MPI.COMM_WORLD.rank}"
    runs = [dict(method="penalty", K=1e5, F_hat=0.0, augment=0, quadrature="nodal", refinement=None),
            dict(method="cross", K=1e5, F_hat=0.0, augment=10, quadrature="nodal", refinement=None)]
    bench.bench("block", out, runs, quiet=True)
    rows = bench.read_rows(out / "block.csv")
    assert len(rows) == 2
    assert all(r["converged"] for r in rows)
    penalty, cross = rows
    assert (penalty["method"], cross["method"], cross["augment"]) == ("penalty", "cross", 10)
    assert math.isclose(penalty["error"], 0.005464, rel_tol=1e-3)  # penetration p/K
    assert cross["error"] < 1e-8
    assert cross["augmentations"] > 0 and penalty["augmentations"] == 0
    assert all(r["dofs"] > 0 and r["wall_time_s"] > 0 and r["newton_iterations"] > 0 for r in rows)
    for name in ("block.json", "block_pareto.png", "block_iterations.png", "block_dofs.png", "block_findings.md"):
        assert (out / name).exists()
    assert "| cross augmented |" in (out / "block_findings.md").read_text()


def test_failed_run_is_recorded_not_raised(tmp_path):
    # an unknown quadrature makes the demo exit with status 2 (argparse)
    row = bench.run_one("block", dict(method="penalty", K=1e5, F_hat=0.0, augment=0, quadrature="bogus",
                                      refinement=None), tmp_path / f"rank{MPI.COMM_WORLD.rank}")
    assert row["converged"] is False and math.isnan(row["error"])


def test_scene_specs_and_commands(tmp_path):
    assert {"block", "hertz", "sphere"} <= set(bench.bench_scenes())
    for scene in bench.bench_scenes():
        runs = bench.sweep(scene, quick=True)
        assert {r["method"] for r in runs} == set(bench.spec(scene)["methods"])
        exact = [m for m in bench.spec(scene)["methods"] if methods.get(m).sweep.kind == "once"]  # once per mesh
        assert sum(r["method"] in exact for r in runs) == len(exact) * len({r["refinement"] for r in runs})
    nitsche = bench.command("hertz", bench.run_config("nitsche", 30.0, refinement=1, steps=4), tmp_path)
    assert nitsche[nitsche.index("--gamma0") + 1] == "30.0" and "--K" not in nitsche
    assert nitsche[-4:] == ["--refinement", "1", "--steps", "4"]
    vi = bench.command("sphere", bench.run_config("vi", 0.0, refinement=0), tmp_path)
    assert vi[vi.index("--level") + 1] == "0"
    # the scene's iterative solver, then the method's direct one: argparse keeps the last
    assert [vi[i + 1] for i, a in enumerate(vi) if a == "--solver"] == ["iterative", "direct"]
    grid = bench.stability_sweep("hertz", quick=True)
    assert {r["steps"] for r in grid} == {1, 4} and len({r["K"] for r in grid if r["method"] == "penalty"}) == 5
    assert sum(r.get("label") == bench.DTOL for r in grid) == 5  # the fewest load steps only
    assert all("-fc_condition_estimate" in r["args"] for r in grid)
    assert {r.get("label") for r in grid if r["F_hat"] > 0} == {"cross F^ = 1 augmented"}
    with pytest.raises(ValueError, match="scene"):
        bench.spec("nosuchscene")


def test_friction_scene_specs(tmp_path):
    """The two-body friction scenes declare an entry: the friction-capable laws the capability matrix
    offers on their axes, a K sweep around the scene's default; mindlin3d on the tests' coarse contact mesh, one
    ratio; mindlin and mindlin3d with the exact condensed Coulomb law once (no --K), their reference."""
    from fenics_contact.app.scenes import ironing, mindlin, mindlin3d, wedges
    from fenics_contact.capabilities import supported

    assert {"ironing", "mindlin", "mindlin3d", "wedges"} <= set(bench.bench_scenes())
    for scene, module in (("ironing", ironing), ("mindlin", mindlin), ("mindlin3d", mindlin3d), ("wedges", wedges)):
        s = bench.spec(scene)
        assert s["axes"]["friction"] and s["axes"]["kind"] == "two-body"
        assert all(supported(method=m, quadrature="nodal", **s["axes"]) for m in s["methods"])
        Ks = sorted({r["K"] for r in bench.sweep(scene, quick=True) if r["method"] == "penalty"})
        assert Ks[0] < module.DEFAULT_K < Ks[-1] and module.DEFAULT_K in Ks
    assert bench.spec("mindlin")["error"] == bench.spec("mindlin3d")["error"] == "c_error_max"
    for scene in ("mindlin", "mindlin3d"):  # the exact condensed Coulomb once (no --K), the reference line
        (exact,) = [r for r in bench.sweep(scene, quick=True) if r["method"] == "coulomb"]
        assert "--K" not in bench.command(scene, exact, tmp_path)
        assert bench.reference_method(scene) == ("coulomb", "the exact coulomb")
    assert "coulomb" in bench.references()
    # mindlin3d's quick sweep: plain runs only (a 3D run costs a minute and more); the full sweep augments too
    quick, full = bench.sweep("mindlin3d", quick=True), bench.sweep("mindlin3d")
    assert len(quick) == 7 and {r["augment"] for r in quick} == {0}
    assert {r["augment"] for r in full} == {0, bench.AUGMENT}
    cmd = bench.command("mindlin3d", bench.run_config("penalty", mindlin3d.DEFAULT_K, refinement=0), tmp_path)
    assert cmd[cmd.index("--h-contact") + 1] == "0.015" and cmd[cmd.index("--ratios") + 1:][:2] == ["0.5", "--solver"]
    assert cmd[cmd.index("--solver") + 1] == "direct"  # the documented rows' LU (the demo defaults to GAMG)


def _row(method, K, error, time_s, augment=0, refinement=0, **kw):
    return {"scene": "hertz", "method": method, "K": K, "F_hat": 0.0, "augment": augment, "quadrature": "nodal",
            "refinement": refinement, "steps": kw.get("steps"), "dofs": 100, "wall_time_s": time_s,
            "newton_iterations": kw.get("newton", 3), "linear_iterations": 3, "augmentations": 0,
            "converged": kw.get("converged", True), "cutbacks": 0, "snes_reason": 2, "error": error,
            "limit_gap": 0.0, "setup_time_s": 1.0, "ratio_to_linear_solve": time_s / 0.1,
            "linear_solve_floor_s": 0.1, "p0": 1.0}


def test_findings_pick_the_fastest_run_within_the_target(tmp_path):
    rows = [_row("penalty", 1e6, 0.02, 0.1), _row("penalty", 1e8, 0.005, 0.3), _row("penalty", 1e7, 0.008, 0.2),
            _row("auglag", 1e6, 0.003, 0.5, augment=10), _row("vi", 0.0, 0.003, 0.4),
            _row("nitsche", 10.0, 0.004, 0.15)]
    text = bench.findings("hertz", rows)
    assert "fastest of the suite's methods within the target: penalty (K 1e+07), 0.200 s" in text
    assert "0.50 x its time" in text  # 0.2 s against SNES VI's 0.4 s
    assert "fastest of the references within the target: nitsche (gamma0 10), 0.150 s" in text
    # the stability heat map draws failed runs too
    grid = [_row(m, K, 0.01, 0.1, steps=n, converged=not (m == "penalty" and K > 1e9))
            for m in ("penalty", "nitsche") for K in (1e6, 1e8, 1e10) for n in (1, 4)]
    bench.plot_stability(grid, tmp_path / "map.png")
    assert (tmp_path / "map.png").stat().st_size > 1000


def test_friction_runs_are_measured_against_the_exact_method(tmp_path):
    """mindlin: each run's stick half-width is compared with the exact condensed Coulomb's on the same mesh (its
    gap), the findings give the time per the exact method's, and the Pareto chart draws it."""
    rows = [{**_row("penalty", 1e7, 0.03, 0.5), "scene": "mindlin", "c_worst": 1.02},
            {**_row("coulomb", 0.0, 0.02, 0.25), "scene": "mindlin", "c_worst": 1.0}]
    bench.add_limit_gap(rows, "mindlin")
    assert np.isclose(rows[0]["limit_gap"], 0.02) and rows[1]["limit_gap"] == 0.0
    text = bench.findings("mindlin", rows)
    assert "gap to coulomb" in text and "| /coulomb |" in text
    assert "the exact coulomb 0.250 s (error 0.02): 2.00 x its time" in text, text
    bench.plot_pareto(rows, tmp_path / "pareto.png")
    assert (tmp_path / "pareto.png").stat().st_size > 1000


def test_ring_through_the_scene_runner(tmp_path):
    """The ring (no demo with --method): the harness builds it. Zavarise et al. (1998): penalty with
    augmentation cycles after the first augmentation, cross-constraints converges; no error figure."""
    out = tmp_path / f"rank{MPI.COMM_WORLD.rank}"
    runs = [bench.run_config("penalty", 1e5, 1), bench.run_config("cross", 1e5, 1)]
    assert bench.command("ring", runs[0], out)[1:4] == ["-m", "fenics_contact.app.bench_run", "--run-scene"]
    penalty, cross = bench.bench("ring", out, runs, quiet=True)
    assert not penalty["converged"] and cross["converged"] and cross["augmentations"] == 1
    assert math.isnan(cross["error"]) and cross["plate_force"] > 0
    text = (out / "ring_findings.md").read_text()
    assert "No error figure" in text and "| penalty augmented | 0/1 |" in text and "| cross augmented | 1/1 |" in text
    assert not (out / "ring_pareto.png").exists() and (out / "ring_iterations.png").exists()


def test_slab_error_from_the_exact_coulomb_reference(tmp_path):
    """Slab, mu = 0.4: the error is u_x(A)'s distance from the exact condensed Coulomb method on the same mesh;
    normal compliance with the Coulomb bound (omega_t = c_n) approaches it as 1 / c_n."""
    out = tmp_path / f"rank{MPI.COMM_WORLD.rank}"
    runs = [bench.run_config("coulomb", 0.0, refinement=0), bench.run_config("compliance", 1e5, refinement=0),
            bench.run_config("compliance", 1e6, refinement=0)]
    exact, coarse, fine = bench.bench("slab", out, runs, quiet=True, pictures=False)
    assert all(r["converged"] for r in (exact, coarse, fine))
    assert exact["error"] == 0.0
    assert 1e-4 < coarse["error"] < 1e-2 and 5 < coarse["error"] / fine["error"] < 20


def test_stability_harness_classifies_the_ring(tmp_path):
    """A tiny stability sweep on the ring (450 dofs): the harness tells a converged run, an ill-conditioned one
    (penalty K = 1e12: Newton stalls at the round-off floor and SNES accepts it on the step length), failed
    ones with their kind (K = 1e16: ill-conditioning; penalty with augmentation: cycling), and PETSc's
    divergence test stopping penalty's
    first overshoot at K = 1e8 (the same run converges without it); the distance from the augmentation limit
    falls like 1/K for penalty."""
    out = tmp_path / f"rank{MPI.COMM_WORLD.rank}"
    cond = ["-fc_condition_estimate"]
    runs = [dict(bench.run_config("auglag", 1e5, 10, steps=1), args=cond),
            dict(bench.run_config("penalty", 1e5, 0, steps=1), args=cond),
            dict(bench.run_config("penalty", 1e12, 0, steps=1), args=cond),
            dict(bench.run_config("penalty", 1e16, 0, steps=1), args=cond),
            dict(bench.run_config("penalty", 1e5, 10, steps=1), args=cond),
            dict(bench.run_config("penalty", 1e8, 0, steps=1), label=bench.DTOL,
                 args=bench.PETSC_DTOL),
            dict(bench.run_config("penalty", 1e8, 0, steps=1), args=cond)]
    rows = bench.run_all("ring", out, runs, quiet=True, timeout=300)
    bench.add_stability_limit(rows, "ring")
    auglag, p5, p12, p16, augmented, dtol, p8 = rows
    assert [r["status"] for r in rows] == ["converged", "converged", "ill_conditioned",
                                            "failed: ill_conditioning", "failed: cycling", "failed: divergence",
                                            "converged"]
    # K = 1e12: accepted on the step length above tolerance; K = 1e16: the same on a Jacobian with a condition
    # estimate above 1e12, a failure
    assert p12["stalled_solves"] >= 1 and p12["residual_final"] > 1e-10 and p12["condition_estimate"] < 1e12
    # the condition estimate grows like K (direct solver: power and inverse iteration)
    assert 300 < p8["condition_estimate"] / p5["condition_estimate"] < 3000
    assert auglag["limit_gap"] == 0.0 and 300 < p5["limit_gap"] / p8["limit_gap"] < 3000
    text = bench.stability_summary(rows)
    assert "| penalty augmented | K | - | - | 1e+05 (cycling) |" in text
    bench.plot_stability(rows, out / "map.png", title="ring")
    assert (out / "map.png").stat().st_size > 1000


def test_reduction_rows_and_chart(tmp_path):
    """The model-reduction rows: p0 and a errors against Hertz, differences from the reduced model (the first row),
    solver time, peak memory and the time saved with its ratio; the chart draws both errors of each variant against
    time and memory."""
    used = dict(variant="sphere: axisymmetric (used)", dofs=1000, p0=20.0, a=0.06, total_force=0.144, error=0.02,
                a_error=0.01, wall_time_s=0.5, memory_peak_mb=200.0, converged=True, newton_iterations=5)
    octant = dict(used, variant="sphere: 3D octant", dofs=12000, p0=19.0, error=0.046, a_error=0.02, wall_time_s=25.0,
                  memory_peak_mb=900.0)
    finer = dict(octant, variant="sphere: 3D octant, level 1", wall_time_s=250.0)
    text, table = bench.reduction_table([used, octant, finer], ["p0", "a", "total_force"])
    lines = text.splitlines()
    assert lines[0] == ("| sphere: axisymmetric (used) | 1000 | 20 | 0.06 | 0.144 | 2.000% / 1.000% | "
                        "0.00% / 0.00% / 0.00% | 0.500 | 200 | - |")
    assert lines[1] == ("| sphere: 3D octant | 12000 | 19 | 0.06 | 0.144 | 4.600% / 2.000% | 5.00% / 0.00% / 0.00% | "
                        "25.000 | 900 | 98% (1/50) |")
    assert all(line.count("|") == bench.REDUCTION_HEADER[0].count("|") for line in lines)
    assert lines[2].endswith("| 250.000 | 900 | 99.8% (1/500) |")  # never a rounded 100 %
    assert table[1]["time_saved"] == pytest.approx(0.98) and table[1]["a_error"] == 0.02
    # the page's rows and chart again from the table's CSV (bench --charts-only)
    out = tmp_path / f"rank{MPI.COMM_WORLD.rank}"
    out.mkdir()
    with open(out / "sphere_reduction.csv", "w", newline="") as f:
        w = csv.DictWriter(f, list(table[0]))
        w.writeheader()
        w.writerows(table)
    assert bench.reduction_report("sphere", out) == text
    assert (out / "sphere_reduction.md").read_text().splitlines()[2:] == lines
    assert (out / "sphere_reduction.png").stat().st_size > 1000


def test_axisphere_bench_entries_are_what_the_grid_offers_on_the_ring(tmp_path):
    """The axisymmetric sphere's benchmarks (rigid plane; two spheres): every method the capability grid offers on
    the ring and no other, over the mesh size at the contact (a float level, read back as such)."""
    from fenics_contact.capabilities import supported

    for scene, kind in (("axisphere", "rigid"), ("axisphere_spheres", "two-body")):
        s = bench.spec(scene)
        offered = {m for m in methods.names() if methods.get(m).sweep.kind != "once" and m != "compliance"
                   and supported(method=m, quadrature="nodal", kind=kind, dim=2, geometry="axisymmetric")}
        assert set(s["methods"]) == offered, (scene, offered)
        runs = bench.sweep(scene, quick=True)
        assert sorted({r["refinement"] for r in runs}) == [0.005, 0.01]
        assert bench._markers(runs) == {None: "o", 0.01: "o", 0.005: "^"}  # the coarser mesh first, as levels
        cmd = bench.command(scene, runs[0], tmp_path)
        assert cmd[cmd.index("--h-contact") + 1] == "0.01"
    rows = [dict(_row("penalty", 1e6, 0.02, 0.1), refinement=0.005), _row("penalty", 1e6, 0.02, 0.1, refinement=2)]
    csv_path = tmp_path / f"rows{MPI.COMM_WORLD.rank}.csv"
    bench.write_rows(rows, csv_path, csv_path.with_suffix(".json"))
    assert [r["refinement"] for r in bench.read_rows(csv_path)] == [0.005, 2]


def test_reduction_only_refuses_a_scene_without_rows(capsys):
    from fenics_contact.app.cli import EXIT_ERROR

    with pytest.raises(SystemExit) as exit_:
        bench_run.main(["--reduction-only", "--scene", "block", "--out", "/nonexistent/never-written"])
    assert exit_.value.code == EXIT_ERROR
    err = capsys.readouterr().err  # one line, from rank 0
    if MPI.COMM_WORLD.rank == 0:
        assert err.count("\n") == 1 and "block" in err and "sphere" in err
    else:
        assert err == ""


def test_oring_bench_entries_are_what_the_grid_offers_on_the_mixed_ring(tmp_path):
    """The O-ring's benchmark: every K-type method the capability grid offers on the axisymmetric P2 mixed section
    with Gauss points, the accuracy rows over the mesh size, the stability map at the whole load with the scene's
    quadrature, and the locking runs: every variant and the reference at every nu, the reference finer."""
    from fenics_contact.app.scenes import oring
    from fenics_contact.capabilities import supported

    s = bench.spec("oring")
    axes = dict(kind="rigid", dim=2, degree=2, model="neohookean-mixed", geometry="axisymmetric")
    offered = {m for m in methods.names() if methods.get(m).sweep.kind != "once" and m != "compliance"
               and supported(method=m, quadrature="gauss", **axes)}
    assert set(s["methods"]) == offered
    runs = bench.sweep("oring", quick=True)
    assert sorted({r["refinement"] for r in runs}) == [0.07, 0.1]
    assert all(supported(method=r["method"], quadrature=r["quadrature"], **axes) for r in runs)
    stab = bench.stability_sweep("oring", quick=True)
    assert stab and all(r["quadrature"] == "gauss" for r in stab)
    cmd = bench.command("oring", stab[0], tmp_path)
    assert cmd[len(cmd) - 1 - cmd[::-1].index("--squeeze") + 1] == repr(oring.SQUEEZE)  # the map's load wins
    lk = s["locking"]
    locking = bench.locking_runs("oring")
    assert len(locking) == len(lk["nu"]) * (len(lk["variants"]) + 1)
    for r in locking:
        cmd = bench.command("oring", r, tmp_path)
        assert cmd[len(cmd) - 1 - cmd[::-1].index("--nu") + 1] == repr(r["nu"])
    h = {r["variant"]: float(r["args"][len(r["args"]) - 1 - r["args"][::-1].index("--h") + 1]) for r in locking}
    assert h[lk["reference"][0]] < min(v for k, v in h.items() if k != lk["reference"][0])
    # the reference is a variant of a method (auglag with augmentations): the findings' ratios are to its run
    assert bench.reference_method("oring") == ("auglag augmented", "auglag augmented")
    text = bench.findings("oring", [_row("penalty", 1e7, 0.02, 0.1), _row("auglag", 1e6, 0.01, 0.4, augment=10)])
    assert "| 0 | 100 | penalty | K 1e+07 | 0.02 | 0 | 3 | 0 | 0.100 | 1.0 | 0.25 |" in text


def test_locking_errors_are_against_the_reference_at_the_same_nu(tmp_path):
    """The locking table: each variant's figures against the reference run at its own nu; a failed run is named,
    never an error figure; the rows survive the CSV."""

    lk = bench.spec("oring")["locking"]
    (v1, _), (v2, _), (v3, _) = lk["variants"]
    ref = lk["reference"][0]
    rows = []
    for nu, scale in ((0.45, 1.0), (0.4999, 2.0)):
        rows += [dict(_row("penalty", 1e6, 0.0, 1.0), variant=ref, nu=nu, force_bore=10.0 * scale, p0_bore=100.0),
                 dict(_row("penalty", 1e6, 0.0, 1.0), variant=v1, nu=nu, force_bore=11.0 * scale, p0_bore=150.0),
                 dict(_row("penalty", 1e6, 0.0, 1.0), variant=v2, nu=nu, force_bore=10.0 * scale, p0_bore=100.0),
                 dict(_row("penalty", 1e6, 0.0, 1.0, converged=False), variant=v3, nu=nu, force_bore=0.0,
                      p0_bore=0.0, failure_kind="divergence")]
    csv_path = tmp_path / f"locking{MPI.COMM_WORLD.rank}.csv"
    bench.write_rows(rows, csv_path, csv_path.with_suffix(".json"))
    back = bench.read_rows(csv_path)
    err = {(r["variant"], r["nu"]): r for r in bench.locking_errors(back, "oring")}
    assert err[(v1, 0.4999)]["force_bore_error"] == pytest.approx(0.1)  # 22 against 20, not against 10
    assert err[(v1, 0.45)]["p0_bore_error"] == pytest.approx(0.5)
    assert err[(v2, 0.4999)]["force_bore_error"] == 0.0
    assert math.isnan(err[(v3, 0.45)]["force_bore_error"])
    text = bench.locking_table(back, "oring")
    line = next(t for t in text.splitlines() if t.startswith(f"| {v3} |"))
    assert line.count("failed (divergence)") == 2
    assert "10.0% / 50.0%" in next(t for t in text.splitlines() if t.startswith(f"| {v1} |"))
