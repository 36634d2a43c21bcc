"""How much memory this process may use, and the least an unknown takes: the bound of the sizes the demos accept."""
from __future__ import annotations

import math
import os
import resource

__all__ = ["BYTES_PER_DOF", "available_memory", "gigabytes", "machine_memory"]

# The least memory one unknown takes in a run (mesh, spaces, forms, vectors, the Jacobian and its factorization or
# multigrid hierarchy): measured 2.5 kB per dof with MUMPS LU (hertz, 5e4 to 2e5 dofs), 1.4 kB with GAMG (sphere,
# 1e4). Below every solver's, so that only a mesh that cannot fit is refused.
BYTES_PER_DOF = 1000.0


def gigabytes(nbytes: float) -> str:
    """``nbytes`` as ``"24.7 GB"`` (``"1e24 GB"`` beyond 1e6 GB)."""
    return f"{nbytes / 1e9:.3g} GB" if nbytes < 1e15 else f"1e{math.log10(nbytes) - 9:.0f} GB"


def machine_memory() -> float:
    """Bytes of physical memory of this machine."""
    return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))


def available_memory() -> tuple[float, str]:
    """Bytes this process may use, the least of the machine's memory, its control group's limit and the
    address-space cap (``ulimit -v``), and a phrase saying which (``"this machine's 24.7 GB"``)."""
    limits = [(machine_memory(), "this machine's {}")]
    try:
        text = open("/sys/fs/cgroup/memory.max").read().strip()
        if text.isdigit():
            limits.append((float(text), "the control group's limit of {}"))
    except OSError:
        pass
    for cap, name in ((resource.RLIMIT_AS, "ulimit -v"), (resource.RLIMIT_DATA, "ulimit -d")):
        soft = resource.getrlimit(cap)[0]
        if soft != resource.RLIM_INFINITY:
            limits.append((float(soft), f"the {{}} this process may use ({name})"))
    nbytes, phrase = min(limits)
    return nbytes, phrase.format(gigabytes(nbytes))
