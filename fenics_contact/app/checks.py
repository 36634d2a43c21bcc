"""Self-checks of the demos: a figure against its scene's reference (closed form, published number, or a
documented converged reference), recorded as ``check`` in ``summary.json`` and logged as one line. A reference
applied beyond its range (Hertz's at a contact half-width ``a/R > HERTZ_RANGE``) is flagged in the check, its
line and the summary's ``warnings``; the check's line notes how many warnings the run has (``check["warnings"]``:
a limit the solver met, a model past its range, a reference out of its range)."""
from __future__ import annotations

import logging
import math

logger = logging.getLogger(__name__)

__all__ = ["HERTZ_RANGE", "hertz_range", "reference_check", "mirror_agreement", "log_check"]

# a/R past which Hertz's reference is flagged. Hertz replaces the circle (sphere) by the parabola (paraboloid)
# R - sqrt(R^2 - x^2) ~ x^2 / (2R) and each body by a half-space; the profile's relative error at the contact edge
# is (a/R)^2 / 4 + O((a/R)^4): 1 % at a/R = 0.2, the size of the scenes' tolerances (2-5 %) on p0.
HERTZ_RANGE = 0.2


def hertz_range(a: float | None, R: float) -> str | None:
    """The flag of a Hertz reference at contact half-width (radius) ``a`` on a radius ``R`` beyond
    :data:`HERTZ_RANGE`; None within it (or without an ``a``)."""
    if a is None or not math.isfinite(a) or a / R <= HERTZ_RANGE:
        return None
    return (f"a/R = {a / R:.3g} > {HERTZ_RANGE:g}: Hertz's reference (parabolic profile, half-spaces) is out of "
            f"its range, its own error ~(a/R)^2/4 = {(a / R) ** 2 / 4:.1%}")


def reference_check(figure: str, value: float | None, reference: float | None, tolerance: float,
                    source: str = "", flag: str | None = None) -> dict:
    """``{figure, value, reference, rel_error, tolerance, passed, source, flag}``: ``rel_error = |value -
    reference| / |reference|``, passed when it is at most ``tolerance``. ``value`` or ``reference`` None (no
    figure: the run failed before its first step; a reference computed from the run's load) fails. ``flag``: why
    the reference is out of its range here (e.g. :func:`hertz_range`), or None."""
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
            "source": source, "flag": flag}


def mirror_agreement(full: list[dict], half: list[dict], tolerance: float, overlap_tolerance: float, *,
                     force: str, contact: str, overlap: str, at: str, models: str, closed: str) -> dict:
    """The check of a full model with self-contact against its half on the symmetry plane (the same problem): the
    largest difference of the figures ``force`` and ``contact`` between the two over the steps past first contact
    (``contact`` > 0 in either), per the step's ``force``, against ``tolerance``; failed too if the full model's
    figure ``overlap`` (a length; > 0 interpenetration) exceeds ``overlap_tolerance`` at any step, or if the contact
    never closed (``closed``: what to do then). ``full``, ``half``: the figures of each step, in step order; ``at``:
    the figure that names a step (e.g. the approach); ``models``: the two models, for the check's source."""
    worst, where, largest = 0.0, None, 0.0
    for f, h in zip(full, half):
        largest = max(largest, f[overlap])
        if h[contact] <= 0 and f[contact] <= 0:
            continue
        for key in (force, contact):
            d = abs(f[key] - h[key]) / h[force]
            if d >= worst:
                worst, where = d, (key, f, h)
    if where is None:
        return reference_check(f"{contact} (full against half)", None, None, tolerance, closed)
    key, f, h = where
    c = reference_check(f"1 + (full - half) / {force}, the worst step past first contact ({key} at {at} "
                        f"{h[at]:.4g})", 1.0 + (f[key] - h[key]) / h[force], 1.0, tolerance,
                        f"{models}; largest overlap {largest:.3g} (at most {overlap_tolerance:.3g})")
    if largest > overlap_tolerance:
        c["passed"] = False
        c["flag"] = f"the two sides overlap by {largest:.3g} > {overlap_tolerance:.3g}"
    c["overlap"] = largest
    return c


def log_check(c: dict, comm=None) -> None:
    """Log the check's line on rank 0: INFO when it passed, WARNING when not (shown also with ``--quiet``)."""
    if comm is not None and comm.rank != 0:
        return
    value = "none (the run failed)" if c["value"] is None else f"{c['value']:.8g}"
    error = "" if c["rel_error"] is None else f", rel. error {c['rel_error']:.2e}"
    reference = "none" if c["reference"] is None else f"{c['reference']:.8g}"
    flag = f" (reference out of its range: {c['flag']})" if c.get("flag") else ""
    n = c.get("warnings") or 0
    noted = f"; the run has {n} warning{'s' if n > 1 else ''} (summary.json)" if n else ""
    logger.log(logging.INFO if c["passed"] and not flag and not n else logging.WARNING,
               f"check: {c['figure']} = {value}, reference {reference} ({c['source']}){error}, "
               f"tolerance {c['tolerance']:.0e}: {'passed' if c['passed'] else 'FAILED'}{flag}{noted}")
