"""The run plumbing: summary.json has the documented figures, reduced over ranks, and a sane time split."""
import json

from fenics_contact.app.run import run
from fenics_contact.app.scenes import build
from fenics_contact.laws import CrossConstraints


def test_summary_has_the_documented_keys(tmp_path_factory, comm):
    out = comm.bcast(str(tmp_path_factory.mktemp("run")) if comm.rank == 0 else None)
    setup = build("block", law=CrossConstraints(1e5, 100.0), comm=comm)
    returned = run(setup, out, "cross", {"K": 1e5, "F_hat": 100.0}, augment_max=10, quiet=True)
    s = json.load(open(f"{out}/summary.json"))
    for key in ("scene", "method", "parameters", "dofs", "ranks", "wall_time_s", "newton_iterations",
                "augmentations", "converged", "contact_pressure", "max_penetration", "steps"):
        assert key in s, key
    assert s["ranks"] == comm.size and s["dofs"] == 90 and s["converged"] and s["augmentations"] == 5
    assert s["newton_iterations"] == sum(len(r) - 1 for r in s["steps"][0]["residuals"])
    split = s["time_split"]
    assert all(v >= 0 for v in split.values()) and sum(split.values()) <= s["solve_time_s"]
    # the fields, checkpoint and progress written after the step are not the solve
    assert 0 < s["output_time_s"] < s["wall_time_s"] and s["solve_time_s"] == s["wall_time_s"] - s["output_time_s"]
    assert s["ratio_to_linear_solve"] == s["solve_time_s"] / s["linear_solve_floor_s"]
    assert s["linear_solve_floor_s"] > 0 and s["ratio_to_linear_solve"] > 1 and s["memory_peak_mb"] > 0
    assert returned["contact_pressure"] == s["contact_pressure"]


def test_augmentation_stopped_at_its_limit_is_in_summary_json_and_noted_by_the_check(tmp_path_factory, comm):
    from fenics_contact.app.checks import reference_check

    out = comm.bcast(str(tmp_path_factory.mktemp("run")) if comm.rank == 0 else None)
    setup = build("block", law=CrossConstraints(1e5, 100.0), comm=comm)  # 5 augmentations to its tolerance
    check = lambda s: reference_check("contact_pressure", s["contact_pressure"], s["contact_pressure"], 1e-3)  # noqa: E731
    run(setup, out, "cross", {"K": 1e5, "F_hat": 100.0}, augment_max=2, quiet=True, check=check)
    s = json.load(open(f"{out}/summary.json"))
    assert s["converged"] and s["augmentations"] == 2
    stopped = [w for w in s["warnings"] if w.startswith("augmentation stopped")]
    assert len(stopped) == 1 and "augment_max = 2 at step 1 (t = 1)" in stopped[0]
    assert s["check"]["passed"] and s["check"]["warnings"] == len(s["warnings"])
