"""The contact methods, each declared once (:class:`Method`), in one registry.

Everything that depends on the method reads its declaration here: the surface factory
(:func:`fenics_contact.contact_surface`, :func:`fenics_contact.two_body_surfaces`), the capability grid
(:mod:`fenics_contact.capabilities`), the command line and the benchmark of :mod:`fenics_contact.app`, and
the docs. The built-in methods are one file each in this package. A method of one's own is one file that
defines its law and calls :func:`register`; a program that should offer it (the demos, the benchmark's child
runs) imports that module, or names it in the environment variable ``FENICS_CONTACT_METHODS`` (module names,
comma separated), which the registry imports on first use.
"""
from __future__ import annotations

import importlib
import os
import re
from typing import Iterator, Mapping

from . import auglag, compliance, coulomb, cross, lagrange, nitsche, penalty, penalty_multiplier, vi
from .spec import Method, Parameter, Rule, Sweep, rule

__all__ = ["Method", "Parameter", "Rule", "Sweep", "rule", "register", "unregister", "get", "names", "methods",
           "of_law", "make_law", "markdown", "METHODS", "PLUGINS"]

PLUGINS = "FENICS_CONTACT_METHODS"  # the environment variable naming modules that register methods

_REGISTRY: dict[str, Method] = {}
_plugins_loaded = False


def register(method: Method, replace: bool = False) -> Method:
    """Add ``method`` to the registry (``ValueError`` if its name is taken, unless ``replace``). Returns it.

    Args:
        method: the :class:`~fenics_contact.methods.Method` declaration.
        replace: replace a method of the same name instead of refusing it.

    Returns:
        ``method``.
    """
    if not isinstance(method, Method):
        raise TypeError(f"register takes a Method, got {type(method).__name__}")
    if method.name in _REGISTRY and not replace:
        raise ValueError(f"a method named {method.name!r} is already registered")
    if not method.name.isidentifier():
        raise ValueError(f"a method name must be an identifier, got {method.name!r}")
    _REGISTRY[method.name] = method
    return method


def unregister(name: str) -> None:
    """Remove the method ``name`` (a test's own method, when done)."""
    _REGISTRY.pop(name, None)


def _load_plugins() -> None:
    global _plugins_loaded
    if _plugins_loaded:
        return
    _plugins_loaded = True
    for module in filter(None, (m.strip() for m in os.environ.get(PLUGINS, "").split(","))):
        importlib.import_module(module)


def methods() -> list[Method]:
    """Every registered method, built-ins first, in registration order."""
    _load_plugins()
    return list(_REGISTRY.values())


def names() -> list[str]:
    """The registered method names."""
    return [m.name for m in methods()]


def get(name: str) -> Method:
    """The method ``name`` (``ValueError`` naming the accepted ones if there is none)."""
    _load_plugins()
    if name not in _REGISTRY:
        raise ValueError(f"unknown contact method {name!r}; accepted: {', '.join(_REGISTRY)}")
    return _REGISTRY[name]


def of_law(law) -> Method | None:
    """The method of a law (friction on top of a law: the law's method); None for a law of one's own that no
    method declares."""
    _load_plugins()
    return _REGISTRY.get(getattr(law, "method", getattr(law, "name", None)))


def make_law(method: str, **params: float):
    """The law of method ``method`` from its parameters by name (see the method's ``parameters``).

    Args:
        method: a registered method's name (``fc.methods.names()``).
        params: the method's parameters by name, e.g. ``K=1e6`` (``Method.parameters``).

    Returns:
        The law (a :class:`Formulation`); ``ValueError`` for an unknown method or parameter.
    """
    return get(method).make_law(**params)


class _Laws(Mapping):
    """Method name -> its law factory, read from the registry (methods registered later included)."""

    def __getitem__(self, name: str):
        return get(name).law if name in names() else _missing(name)

    def __iter__(self) -> Iterator[str]:
        return iter(names())

    def __len__(self) -> int:
        return len(names())

    def __repr__(self) -> str:
        return f"METHODS({', '.join(names())})"


def _missing(name: str):
    raise KeyError(name)


METHODS: Mapping = _Laws()

for _module in (penalty, cross, auglag, compliance, vi, coulomb, lagrange, penalty_multiplier, nitsche):
    register(_module.METHOD)
del _module


def _cell(text: str) -> str:
    """``text`` in a Markdown table cell: ``|`` and a ``<`` that would open an HTML tag (``<g>``) escaped."""
    return re.sub(r"<(?=[A-Za-z/!?])", r"\\<", text).replace("|", r"\|")


def markdown() -> str:
    """The registered methods as Markdown (``docs/methods.md``): each method's formulation, parameters (option,
    meaning, range, default), augmentation default, friction, two-body support and benchmark sweep."""
    from .spec import RANGES

    lines = ["# Contact methods", "",
             "Generated by `python -m fenics_contact.methods > docs/methods.md` from the method declarations "
             "(`fenics_contact/methods/`); do not edit. Adding a method: `docs/adding_a_method.md`; what combines "
             "with what: `docs/capabilities.md`.", "",
             "| method | formulation | augmentations | friction | two bodies | benchmark sweep |",
             "|---|---|---|---|---|---|"]
    friction = {"none": "no", "law": "on top of the law (`--mu`, `--c-t`, `--tresca`)", "own": "its own `mu`"}
    for m in methods():
        sweep = "once" if m.sweep.kind == "once" else f"{m.sweep.parameter} ({m.sweep.kind})"
        lines.append(f"| `{m.name}` | {_cell(m.summary)} | {m.augment} | {friction[m.friction]} | "
                     f"{'yes' if m.two_body is not None else 'no: ' + (m.no_two_body or 'refused')} | {sweep} |")
    lines += ["", "## Parameters", "", "| method | parameter | option | meaning | accepted | default |",
              "|---|---|---|---|---|---|"]
    for m in methods():
        for p in m.parameters:
            default = "the scene's" if p.default is None else f"`--{p.default.replace('_', '-')}`" if isinstance(
                p.default, str) else f"{p.default:g}"
            lines.append(f"| `{m.name}` | `{p.name}` | `--{p.option.replace('_', '-')}` | {_cell(p.help)} | "
                         f"{RANGES[p.range][1]} | {default} |")
    return "\n".join(lines) + "\n"
