"""The peer side by side: dolfinx_contact's own demos and this suite's demos on the same four cases (two-body
Hertz 2D and 3D, the Cattaneo-Mindlin friction cylinders, the sliding wedges), in one run, in the Debian 13 root
(dolfinx 0.9) where both codes run; then the page docs/bench/peer.md with one table and one accuracy-against-time
chart per case (scripts/peer/page.py).

    python scripts/peer/run.py --peer-src /path/to/asimov-contact [--peer-prefix /opt/peer] [--quick]

The peer is not built here: it must be installed in the root (its C++ library and Python package under
``--peer-prefix``, as its own README describes) before this runs; ``--peer-src`` is its source checkout, whose
demos are run unchanged (scripts/peer/peer_case.py). Each job is a fresh serial process; its figures go to
``--out``/rows.json with the run's record (machine, date, load average, command); the rows of cases a run does
not redo are kept with their own run's record.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from fenics_contact.app.run_record import machine  # noqa: E402

DEB13 = Path(os.environ.get("DEB13", Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
                            / "fenics_contact" / "debian13"))
HERTZ2D = ["--plate", "meshed", "--E", "200", "--nu", "0.3", "--R", "8", "--load", "10", "--plate-E", "200",
           "--plate-width", "32", "--plate-depth", "16"]
# The peer's 3D case: a half sphere (R 8) pressed by a volume force on a 20 x 20 x 20 box (its load 10 is the
# force on a whole sphere: the half sphere carries 5), both
# E 200, nu 0.3; Hertz: a = 0.65, approach a^2 / R = 0.0526. Here the octant is driven by that approach (the
# sphere scene's two-body case is displacement controlled) and its error is against Hertz at its own force.
HERTZ3D = ["--plate", "meshed", "--E", "200", "--nu", "0.3", "--R", "8", "--approach", "0.0526",
           "--plate-width", "10", "--plate-depth", "10"]
# The peer's cylinders: two quarter disks R 8, E 200, nu 0.3, mu 0.3, pressed then sheared (displacement
# driven); Mindlin's c at the last step's Q / (mu P). Here the mindlin scene at the same material, mu and R.
MINDLIN = ["--E", "200", "--nu", "0.3", "--R", "8", "--mu", "0.3"]
# The peer's wedges: mu 0.5, alpha = atan 0.1 = 5.7106 deg, E 200, nu 0.3.
WEDGES = ["--E", "200", "--nu", "0.3", "--mu", "0.5", "--alpha", "5.710593137499643"]

CASES = {
    "hertz2d": {"title": "Two-body Hertz, 2D (cylinder on a block, R 8, E 200, nu 0.3, load 10 per length)",
                "peer": ("python/demos/hertz_contact/demo_hertzian_contact.py", ["--problem", "2"], "--res",
                         [0.4, 0.2, 0.1], [0.4, 0.2]),
                "ours": ("hertz", HERTZ2D, "--refinement", [0, 1, 2], [0, 1],
                         {"nitsche": [], "coulomb": ["--steps", "1"]}),
                "figure": ("p0", "p0_error", "p0_hertz")},
    "hertz3d": {"title": "Two-body Hertz, 3D (sphere on a block, R 8, E 200, nu 0.3, load 5)",
                "peer": ("python/demos/hertz_contact/demo_hertzian_contact.py", ["--3D"], "--res",
                         [2.0, 1.0, 0.5], [2.0, 1.0]),
                "ours": ("sphere", HERTZ3D, "--level", [0, 1], [0],
                         {"nitsche": ["--solver", "iterative"], "coulomb": []}),
                "figure": ("p0", "p0_error", "p0_hertz")},
    "cylinders": {"title": "Cattaneo-Mindlin friction cylinders, 2D (R 8, E 200, nu 0.3, mu 0.3)",
                  "peer": ("python/demos/hertz_contact/demo_friction_cylinders.py", [], "--res", [0.4, 0.2],
                           [0.4]),
                  "ours": ("mindlin", MINDLIN, "--refinement", [0, 1], [0],
                           {"nitsche": [], "nitsche-small": ["--sliding", "small"], "coulomb": []}),
                  "figure": ("c_worst", "c_error_max", "c_ref_{ratio_worst:g}")},
    "wedges": {"title": "Sliding wedges, 2D (mu 0.5, alpha = atan 0.1, E 200, nu 0.3)",
               "peer": ("python/demos/demo_sliding_wedges.py", [], "--res", [0.4, 0.2, 0.1], [0.4, 0.2]),
               "ours": ("wedges", WEDGES, None, [None], [None], {"nitsche": [], "cross": []}),
               "figure": ("ratio", "ratio_error", "ratio_reference")},
}


def _chroot(cmd: str, env: dict[str, str], timeout: float) -> subprocess.CompletedProcess:
    # Debian 13's Open MPI may hang here without these transport choices (as in scripts/debian13.sh).
    base = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMPI_MCA_btl": "self,sm",
            "OMPI_MCA_pml": "ob1", "OMPI_MCA_rmaps_base_oversubscribe": "1", "OPENBLAS_NUM_THREADS": "1",
            "OMP_NUM_THREADS": "1", "UCX_LOG_LEVEL": "fatal", "HOME": "/root", **env}
    args = ["chroot", str(DEB13), "/usr/bin/env", *[f"{k}={v}" for k, v in base.items()], "/bin/sh", "-c", cmd]
    return subprocess.run(args, capture_output=True, text=True, timeout=timeout)


def _peer_env(prefix: str) -> dict[str, str]:
    return {"PYTHONPATH": f"{prefix}/python", "LD_LIBRARY_PATH": f"{prefix}/lib"}


def _check(args) -> str | None:
    """A one-line reason this run cannot be done, or None."""
    if os.geteuid() != 0:
        return "needs root (chroot into the Debian 13 root)"
    if not (DEB13 / "usr/bin/python3").exists():
        return f"no Debian 13 root at {DEB13} (make it with scripts/debian13.sh, or set DEB13)"
    src = Path(args.peer_src)
    missing = [c["peer"][0] for c in CASES.values() if not (src / c["peer"][0]).is_file()]
    if missing:
        return f"--peer-src {src}: not an asimov-contact checkout (no {missing[0]})"
    probe = _chroot("python3 -c 'import dolfinx_contact.cpp'", _peer_env(args.peer_prefix), 300)
    if probe.returncode != 0:
        return (f"--peer-prefix {args.peer_prefix}: dolfinx_contact is not importable in {DEB13} "
                "(install it there first, as its README describes)")
    return None


def _job(kind: str, case: str, method: str, level, cmd: str, env: dict, timeout: float, result) -> dict:
    t0 = time.perf_counter()
    try:
        proc = _chroot(cmd, env, timeout)
        # exit 3: this suite's demo ran to the end and its own check failed (the row keeps its figures)
        ok, log = proc.returncode in (0, 3), proc.stdout[-2000:] + proc.stderr[-2000:]
        check_failed = proc.returncode == 3
    except subprocess.TimeoutExpired:
        ok, log, check_failed = False, f"timed out after {timeout:.0f} s", False
    row = {"code": kind, "case": case, "method": method, "level": level, "command": cmd,
           "elapsed_s": time.perf_counter() - t0}
    if ok:
        try:
            row.update(result())
        except (OSError, ValueError, KeyError) as err:
            ok, log = False, f"no result: {err}"
    row["status"] = "done" if ok else "failed"
    if ok and check_failed:
        row["check"] = "failed"
    if not ok:
        row["log"] = log
    print(f"peer: {kind} {case} {method} {level}: {row['status']} "
          f"(error {row.get('error')}, {row.get('wall_time_s')} s)", flush=True)
    return row


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--peer-src", required=True, help="asimov-contact source checkout (v0.9.0)")
    parser.add_argument("--peer-prefix", default="/opt/peer",
                        help="where the peer is installed inside the root (lib/, python/) (default: /opt/peer)")
    parser.add_argument("--out", default=str(ROOT / "results" / "peer"), help="output folder")
    parser.add_argument("--docs", default=str(ROOT / "docs" / "bench"), help="folder of the page")
    parser.add_argument("--cases", nargs="+", choices=list(CASES), default=list(CASES))
    parser.add_argument("--quick", action="store_true", help="the coarser meshes only")
    parser.add_argument("--timeout", type=float, default=3600.0, help="seconds per job (default: 3600)")
    args = parser.parse_args(argv)
    reason = _check(args)
    if reason:
        print(f"peer: cannot run: {reason}", file=sys.stderr)
        return 2
    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    # The project and the peer's demos are copied into the root (no bind mount needed), one folder per checkout
    # and output folder, so that two runs do not share one.
    project = f"peer-project-{hashlib.md5(f'{ROOT}:{out}'.encode()).hexdigest()[:8]}"
    dst = DEB13 / project
    shutil.rmtree(dst, ignore_errors=True)
    dst.mkdir(parents=True)
    for name in ("pyproject.toml", "fenics_contact", "demos", "scripts", "README.md"):
        (shutil.copytree if (ROOT / name).is_dir() else shutil.copy2)(ROOT / name, dst / name)
    shutil.copytree(Path(args.peer_src) / "python" / "demos", dst / "peer_demos" / "python" / "demos")
    record = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "machine": machine(),
              "load_average": round(os.getloadavg()[0], 1), "command": " ".join(["python scripts/peer/run.py",
                                                                                  *(argv or sys.argv[1:])]),
              "peer": _peer_version(args.peer_src),
              "dolfinx": _chroot("python3 -c 'import dolfinx; print(dolfinx.__version__)'", {}, 300)
              .stdout.strip().splitlines()[-1:]}
    record["cases"] = list(args.cases)
    # Rows of cases this run does not redo are kept, with the record of the run that measured them.
    earlier = json.loads((out / "rows.json").read_text()) if (out / "rows.json").exists() else {"runs": [], "rows": []}
    runs = [dict(r, cases=[c for c in r["cases"] if c not in args.cases]) for r in earlier["runs"]]
    runs = [r for r in runs if r["cases"]] + [record]
    kept = [r for r in earlier["rows"] if r["case"] not in args.cases]
    rows = []
    for case in args.cases:
        spec = CASES[case]
        demo, pargs, popt, plevels, pquick = spec["peer"]
        for res in (pquick if args.quick else plevels):
            name = f"peer-{case}-{res}.json"
            cmd = (f"cd /{project} && python3 scripts/peer/peer_case.py {case} /{project}/peer_demos/{demo} "
                   f"results/{name} -- {' '.join(pargs)} {popt} {res}")
            rows.append(_job("dolfinx_contact", case, "nitsche", res, cmd, _peer_env(args.peer_prefix),
                             args.timeout, lambda n=name: json.loads((dst / "results" / n).read_text())))
        scene, oargs, oopt, olevels, oquick, methods = spec["ours"]
        value, error, reference = spec["figure"]
        for method, margs in methods.items():  # a label: the method, then after "-" what its arguments change
            for level in (oquick if args.quick else olevels):
                run = f"results/ours-{case}-{method}-{level}"
                cmd = (f"cd /{project} && PYTHONPATH=/{project} python3 demos/{scene}.py "
                       f"--method {method.split('-')[0]} "
                       f"{' '.join(oargs + margs)} {'' if oopt is None else f'{oopt} {level}'} --out {run} "
                       "--overwrite --no-xdmf --no-pictures --quiet")
                rows.append(_job("fenics_contact", case, method, level, cmd, {}, args.timeout,
                                 lambda r=run, v=value, e=error, f=reference: _ours(dst / r / "summary.json", v, e,
                                                                                      f)))
        (out / "rows.json").write_text(json.dumps({"runs": runs, "rows": kept + rows}, indent=1) + "\n")
    from page import write_page  # scripts/peer/page.py (this script's folder is on sys.path)

    write_page(out / "rows.json", Path(args.docs))
    return 0 if all(r["status"] == "done" for r in rows) else 3


def _ours(summary: Path, value: str, error: str, reference: str) -> dict:
    """A row from this suite's demo summary: ``value``, ``error`` and ``reference`` (a key, formatted with the
    summary's figures) name the case's figure, its relative error and its closed form."""
    s = json.loads(summary.read_text())
    if not s.get("converged", s.get("status") == "converged"):
        raise ValueError(f"status {s.get('status')}")
    return {"dofs": s["dofs"], "newton_iterations": s["newton_iterations_spent"],
            "linear_solves": s["newton_iterations_spent"], "krylov_iterations": s.get("linear_iterations"),
            "wall_time_s": s["wall_time_s"], "total_time_s": s["wall_time_s"] + s.get("setup_time_s", 0.0),
            "figure": value, "value": s[value], "reference": s.get(reference.format(**s)), "error": s[error]}


def _peer_version(src: str) -> str:
    out = subprocess.run(["git", "-C", src, "describe", "--tags", "--always"], capture_output=True, text=True)
    return out.stdout.strip() or "unknown"


if __name__ == "__main__":
    sys.exit(main())
