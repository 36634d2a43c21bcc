"""The speed-against-accuracy harness: the Pareto front, and a two-run sweep on the block."""
import math

import numpy as np
from mpi4py import MPI

from fenics_contact import bench


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
    assert (out / "block.json").exists() and (out / "block_pareto.png").exists()
    assert (out / "block_iterations.png").exists()


def test_failed_run_is_recorded_not_raised(tmp_path):
    # an unknown quadrature makes the demo exit with status 2 (argparse)
    row = bench.run_one("block", dict(method="penalty", K=1e5, F_hat=0.0, augment=0, quadrature="bogus",
                                      refinement=None), tmp_path / f"rank{MPI.COMM_WORLD.rank}")
    assert row["converged"] is False and math.isnan(row["error"])
