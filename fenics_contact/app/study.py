"""What the studies of the demos folder share (``demos/scaling.py``, ``demos/friction_scaling.py``): a demo run in a
fresh process (serial or ``mpirun -n N``), log-log slopes, and the rows written as CSV and JSON."""
from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import time
from pathlib import Path

import numpy as np

from .bench import child_env

__all__ = ["run_demo", "slope", "write_rows"]


def run_demo(cmd: list[str], folder: Path, ranks: int, env: dict | None = None,
             existing: bool = False) -> tuple[dict, int, float]:
    """Run the demo command ``cmd`` (writing its summary.json to ``folder``) in a fresh process, under ``mpirun -n
    ranks`` if ``ranks > 1``, its output kept in ``folder/log.txt``; ``env``: variables added to the environment;
    ``existing``: read a summary.json already in ``folder`` instead of running. Returns the summary ({} if none),
    the exit status (-1: read, not run) and the seconds the process took."""
    folder.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    if existing and (folder / "summary.json").exists():
        status = -1
    else:
        full = child_env()  # a fresh job, not a member of ours; mpirun keeps the run-as-root settings
        full.update(env or {})
        if ranks > 1:
            cmd = [shutil.which("mpirun") or "mpirun", "-n", str(ranks), *cmd]
            full.update({"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
                         "OMPI_MCA_rmaps_base_oversubscribe": "1"})
        (folder / "summary.json").unlink(missing_ok=True)
        proc = subprocess.run(cmd, capture_output=True, text=True, env=full)
        (folder / "log.txt").write_text(proc.stdout + proc.stderr)
        status = proc.returncode
    summary = json.loads((folder / "summary.json").read_text()) if (folder / "summary.json").exists() else {}
    return summary, status, time.perf_counter() - start


def slope(x, y) -> float:
    """The log-log slope of ``y`` against ``x`` (least squares)."""
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def write_rows(out: Path, name: str, rows: list[dict], **extra) -> None:
    """``rows`` as ``out/<name>.csv`` and, with ``extra`` and the machine (cores, load average: a loaded machine's
    timings are noisy), as ``out/<name>.json``."""
    with open(out / f"{name}.csv", "w", newline="") as f:
        w = csv.DictWriter(f, list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    machine = {"cpus": os.cpu_count(), "load_average": os.getloadavg()}
    (out / f"{name}.json").write_text(json.dumps({"rows": rows, **extra, "machine": machine}, indent=1,
                                                 default=float) + "\n")
