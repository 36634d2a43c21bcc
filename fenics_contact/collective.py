"""Collective calls: methods every rank must call, in the same order (they reduce or gather over the ranks). One
rank alone in such a call waits for the others for ever, without a message; with the environment variable
``FENICS_CONTACT_COLLECTIVE_TIMEOUT`` set to seconds, every call wrapped by :func:`collective` first meets the other
ranks (a non-blocking barrier) and a rank that waits longer than that aborts the job with a message naming the
call, as does a meeting of ranks that called different methods. Off (unset): one look-up of the variable per call.
"""
from __future__ import annotations

import functools
import os
import sys
import time

__all__ = ["ENV", "collective", "meet"]

ENV = "FENICS_CONTACT_COLLECTIVE_TIMEOUT"


def _timeout() -> float | None:
    value = os.environ.get(ENV)
    if not value:
        return None
    try:
        seconds = float(value)
    except ValueError:
        raise ValueError(f"{ENV} must be a number of seconds > 0, got {value!r}") from None
    if not seconds > 0:
        raise ValueError(f"{ENV} must be a number of seconds > 0, got {value!r}")
    return seconds


def meet(comm, name: str, seconds: float, abort: bool = True) -> None:
    """Wait at most ``seconds`` for every rank of ``comm`` to reach the call ``name``, then check that they all
    called ``name``. A rank that waits longer (or a mismatch) writes the message to stderr and aborts the job
    (``abort=False``: raises ``RuntimeError`` with it instead)."""
    request = comm.Ibarrier()
    deadline = time.monotonic() + seconds
    message = None
    while not request.Test():
        if time.monotonic() > deadline:
            message = (f"{name} is collective: rank {comm.rank} waited {seconds:g} s ({ENV}) for the other "
                       f"{comm.size - 1} rank(s) to call it; call it on every rank, then print on rank 0")
            break
        time.sleep(1e-3)
    if message is None:
        names = comm.allgather(name)
        if len(set(names)) > 1:
            message = f"collective calls out of step: the ranks called {names} together; call them in one order"
    if message is None:
        return
    if not abort:
        raise RuntimeError(message)
    sys.stderr.write(f"error: {message}\n")
    sys.stderr.flush()
    comm.Abort(1)


def collective(method):
    """``method`` (of an object with ``comm``) checked by :func:`meet` when ``FENICS_CONTACT_COLLECTIVE_TIMEOUT``
    is set."""
    @functools.wraps(method)
    def checked(self, *args, **kwargs):
        seconds = _timeout()
        if seconds is not None and getattr(self, "comm", None) is not None and self.comm.size > 1:
            meet(self.comm, f"{type(self).__name__}.{method.__name__}()", seconds)
        return method(self, *args, **kwargs)

    checked.collective = True
    return checked
