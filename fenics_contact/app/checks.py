"""Self-checks of the demos: a figure against its scene's reference (closed form, published number, or a
documented converged reference), recorded as ``check`` in ``summary.json`` and logged as one line."""
from __future__ import annotations

import logging
import math

logger = logging.getLogger(__name__)

__all__ = ["reference_check", "log_check"]


def reference_check(figure: str, value: float | None, reference: float | None, tolerance: float,
                    source: str = "") -> dict:
    """``{figure, value, reference, rel_error, tolerance, passed, source}``: ``rel_error = |value - reference| /
    |reference|``, passed when it is at most ``tolerance``. ``value`` or ``reference`` None (no figure: the run
    failed before its first step; a reference computed from the run's load) fails."""
    if reference is not None and not (math.isfinite(reference) and reference != 0.0):
        raise ValueError(f"check {figure!r}: the reference must be finite and non-zero, got {reference!r}")
    if not tolerance > 0:
        raise ValueError(f"check {figure!r}: the tolerance must be > 0, got {tolerance!r}")
    has_value = value is not None and math.isfinite(value)
    ok = has_value and reference is not None
    rel = abs(value - reference) / abs(reference) if ok else None
    return {"figure": figure, "value": float(value) if has_value else None,
            "reference": None if reference is None else float(reference),
            "rel_error": rel, "tolerance": float(tolerance), "passed": bool(ok and rel <= tolerance),
            "source": source}


def log_check(c: dict, comm=None) -> None:
    """Log the check's line on rank 0: INFO when it passed, WARNING when not (shown also with ``--quiet``)."""
    if comm is not None and comm.rank != 0:
        return
    value = "none (the run failed)" if c["value"] is None else f"{c['value']:.8g}"
    error = "" if c["rel_error"] is None else f", rel. error {c['rel_error']:.2e}"
    reference = "none" if c["reference"] is None else f"{c['reference']:.8g}"
    logger.log(logging.INFO if c["passed"] else logging.WARNING,
               f"check: {c['figure']} = {value}, reference {reference} ({c['source']}){error}, "
               f"tolerance {c['tolerance']:.0e}: {'passed' if c['passed'] else 'FAILED'}")
