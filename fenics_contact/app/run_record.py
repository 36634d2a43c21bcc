"""The record of a benchmark run: the machine (CPU model, cores, memory, from /proc), the dolfinx and PETSc it ran
on, the date, the commit and the command, written as ``run.json`` into the run's output folder and read by the
benchmark pages."""
from __future__ import annotations

import json
import os
import platform
import subprocess
from datetime import datetime, timezone
from pathlib import Path
from typing import Sequence

__all__ = ["RUN_FILE", "PARTS", "machine", "versions", "record_run", "read_runs"]

RUN_FILE = "run.json"  # the run's record in the benchmark's output folder
# The parts of a scene's results a run may compute: its sweep (findings, charts), stability map, locking map, model
# reduction (the files ``<scene>.csv``, ``<scene>_<part>.md`` and their charts)
PARTS = ("sweep", "stability", "locking", "reduction")


def machine() -> dict:
    """CPU model, logical cores and memory (GB) of this machine, from /proc (``unknown`` where not readable),
    and the operating system."""
    cpu, memory = "unknown", None
    try:
        cpu = next(line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                   if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    try:
        kb = next(int(line.split()[1]) for line in Path("/proc/meminfo").read_text().splitlines()
                  if line.startswith("MemTotal:"))
        memory = round(kb / 1024**2, 1)
    except (OSError, StopIteration, ValueError):
        pass
    system = platform.platform()
    try:
        system = next(line.split("=", 1)[1].strip().strip('"') for line in
                      Path("/etc/os-release").read_text().splitlines() if line.startswith("PRETTY_NAME="))
    except (OSError, StopIteration):
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "memory_gb": memory, "system": system}


def versions() -> dict:
    """The versions of dolfinx and PETSc this Python imports (``unknown`` where one is not importable)."""
    out = {"dolfinx": "unknown", "petsc": "unknown"}
    try:
        import dolfinx

        out["dolfinx"] = dolfinx.__version__
        from petsc4py import PETSc

        out["petsc"] = ".".join(str(v) for v in PETSc.Sys.getVersion())
    except ImportError:
        pass
    return out


def _load_average() -> float | None:
    """The 1-minute load average (other jobs share the cores: times are noisy above the core count)."""
    try:
        return round(os.getloadavg()[0], 1)
    except OSError:
        return None


def _commit(root: Path) -> str:
    try:
        out = subprocess.run(["git", "-C", str(root), "rev-parse", "--short=12", "HEAD"], capture_output=True,
                             text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return "unknown"
    return out.stdout.strip() if out.returncode == 0 and out.stdout.strip() else "unknown"


def record_run(out: str | Path, argv: Sequence[str], scenes: Sequence[str],
               parts: Sequence[str] | None = None) -> dict:
    """Add this run to ``<out>/run.json`` (the runs whose results are in ``out``): this machine, the dolfinx and
    PETSc versions (:func:`versions`), the date (UTC),
    the commit of the package's checkout, the command ``python demos/bench.py <argv>``, the load average at the
    start, the ``scenes`` it runs and, if given, the ``parts`` of their results it computes (of ``PARTS``: the
    others in ``out`` are an earlier run's); an earlier run keeps
    only the scenes this one does not rerun. Returns the new run's record."""
    run = {"date": datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
           "commit": _commit(Path(__file__).resolve().parents[2]),
           "command": " ".join(["python demos/bench.py", *argv]), "machine": machine(), **versions(),
           "load_average": _load_average(), "scenes": list(scenes), **({} if parts is None else {"parts": list(parts)})}
    path = Path(out) / RUN_FILE
    earlier = json.loads(path.read_text())["runs"] if path.exists() else []
    kept = [dict(r, scenes=[s for s in r["scenes"] if s not in run["scenes"]]) for r in earlier]
    Path(out).mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"runs": [r for r in kept if r["scenes"]] + [run]}, indent=1) + "\n")
    return run


def read_runs(results: str | Path) -> list[dict]:
    """The records of the runs whose results are in ``results``, oldest first (``ValueError`` naming the folder
    if it has none: the pages need the machine and date)."""
    path = Path(results) / RUN_FILE
    if not path.exists():
        raise ValueError(f"{results} has no {RUN_FILE}: not the output folder of a benchmark run (make bench)")
    return json.loads(path.read_text())["runs"]
