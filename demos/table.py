"""Print one table of every ``summary.json`` under a results folder: scene, method, figures, error, time."""
import json
import sys
from pathlib import Path

FIGURES = {"block": ("contact_pressure", "exact_pressure", "pressure_error"),
           "hertz": ("p0", "p0_hertz", "p0_error"), "sphere": ("p0", "p0_hertz", "p0_error"),
           "slab": ("ux_A", "ux_A_frictionless", None),  # the reference is the mu = 0 closed form
           "pin": ("contact_angle_deg", None, None)}  # no published value: see README, pin
# ring and seal have no reference value: their summaries give iterations and time (methods.md compares methods)

root = Path(sys.argv[1] if len(sys.argv) > 1 else "results")
rows = [json.loads(p.read_text()) for p in sorted(root.glob("*/summary.json"))]
print(f"{'scene':8s} {'method':8s} {'ranks':>5s} {'dofs':>7s} {'figure':>16s} {'value':>12s} {'reference':>12s} "
      f"{'rel. error':>10s} {'newton':>6s} {'aug':>4s} {'time s':>7s}")
for s in rows:
    name, ref, err = FIGURES.get(s["scene"], (None, None, None))
    value, reference, error = (s.get(k, float("nan")) for k in (name, ref, err)) if name else (0, 0, 0)
    print(f"{s['scene']:8s} {s['method']:8s} {s['ranks']:5d} {s['dofs']:7d} {name or '-':>16s} {value:12.6g} "
          f"{reference:12.6g} {error:10.2e} {s['newton_iterations']:6d} {s['augmentations']:4d} "
          f"{s['wall_time_s']:7.2f}")
