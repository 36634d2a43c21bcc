"""What a contact method declares, once: :class:`Method`, its :class:`Parameter` s, its capability :class:`Rule` s
and its benchmark :class:`Sweep`. Plain data: this module imports no surface, so every part of the suite (the
surface factory, the capability grid, the command line, the benchmark, the docs) can read a declaration."""
from __future__ import annotations

import importlib
import math
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

__all__ = ["Parameter", "Rule", "Sweep", "Method", "rule", "resolve", "RANGES"]

# Accepted ranges of a parameter: name -> (test, words)
RANGES: dict[str, tuple[Callable[[float], bool], str]] = {
    "positive": (lambda v: v > 0.0, "a finite number > 0"),
    "nonnegative": (lambda v: v >= 0.0, "a finite number >= 0"),
    "exponent": (lambda v: v >= 1.0, "a finite number >= 1"),
    "unit": (lambda v: 0.0 <= v < 1.0, "a finite number in [0, 1)"),
    "sign": (lambda v: -1.0 <= v <= 1.0, "a finite number in [-1, 1]"),
}


@dataclass(frozen=True)
class Parameter:
    """A parameter of a method's law.

    Args:
        name: keyword of the law factory (``K_hat``).
        option: the command-line option it is given by, without dashes (``K`` for ``--K``); several methods may
            share one option (``--K`` is the penalty of several laws).
        help: what it is, with its units.
        range: one of :data:`RANGES`.
        default: its default value; ``None``: the scene's (``--K``: scaled with E / h); a string: the value of
            that other option (``c_n`` defaults to ``--K``).
    """

    name: str
    option: str
    help: str
    range: str = "positive"
    default: float | str | None = None

    def __post_init__(self):
        if self.range not in RANGES:
            raise ValueError(f"parameter {self.name}: range must be one of {tuple(RANGES)}, got {self.range!r}")

    def check(self, value: float) -> float:
        """``value`` as a float if it is in the accepted range, else ``ValueError`` naming the parameter."""
        test, words = RANGES[self.range]
        value = float(value)
        if not (math.isfinite(value) and test(value)):
            raise ValueError(f"{self.option} must be {words}, got {value!r}")
        return value


@dataclass(frozen=True)
class Rule:
    """Refuse every combination whose axis values are all in ``when`` (axis -> refused values); ``use``: what to
    use instead; ``why``: the reason, for the docs."""

    when: Mapping[str, tuple]
    use: str
    why: str


def rule(use: str, why: str, **when: Any) -> Rule:
    """A :class:`Rule` from keywords (a single value or a tuple of values per axis)."""
    return Rule({k: tuple(v) if isinstance(v, (tuple, list)) else (v,) for k, v in when.items()}, use, why)


@dataclass(frozen=True)
class Sweep:
    """How the benchmark sweeps a method and draws it.

    Args:
        kind: ``wide`` (the swept parameter over the wide range of exponents around the scene's K), ``narrow``
            (the small range), ``gamma0`` (the Nitsche values), ``once`` (no parameter: once per mesh, nodal).
        parameter: the option swept (``K``, ``gamma0``; None for ``once``).
        augmented: also run with augmentation (the augmented variant of the method).
        colour: the charts' colour (a matplotlib colour name).
        size: the charts' marker size.
        reference: what a user would pick instead of the suite's penalty-type laws (drawn as a reference).
    """

    kind: str = "narrow"
    parameter: str | None = "K"
    augmented: bool = False
    colour: str = "tab:gray"
    size: float = 7.0
    reference: bool = False


@dataclass(frozen=True)
class Method:
    """A contact method, declared once.

    Args:
        name: the method's name (``--method``, ``make_law``).
        summary: one line: the formulation.
        law: the law factory: ``law(**{p.name: value})`` returns its :class:`~fenics_contact.laws.ContactLaw`.
        parameters: the law factory's parameters.
        rigid: builds the surface against a rigid obstacle: a callable or ``"module:function"`` with the
            signature of :func:`fenics_contact.methods.builders.law_surface`.
        two_body: builds the two-body surfaces (signature of :func:`fenics_contact.methods.builders.law_two_body`),
            or None: two bodies are refused, for the reason ``no_two_body``.
        no_two_body: why two bodies are refused (with ``two_body=None``): the capability grid's reason.
        self_contact: builds the surfaces of a surface against itself (signature of
            :func:`fenics_contact.methods.builders.law_self`), or None: self-contact is refused.
        augment: default augmentations per load step (0: none).
        friction: ``none`` (no tangential law), ``law`` (friction on top of the law: ``Friction(law, ...)``) or
            ``own`` (the law's own parameter ``mu``).
        rules: the capability rules of this method (:mod:`fenics_contact.capabilities` adds the ones that follow
            from ``two_body`` and ``friction``).
        sweep: how the benchmark runs it.
    """

    name: str
    summary: str
    law: Callable[..., Any]
    parameters: tuple[Parameter, ...] = ()
    rigid: Callable | str = "fenics_contact.methods.builders:law_surface"
    two_body: Callable | str | None = "fenics_contact.methods.builders:law_two_body"
    no_two_body: str = ""
    self_contact: Callable | str | None = None
    augment: int = 0
    friction: str = "none"
    rules: tuple[Rule, ...] = ()
    sweep: Sweep = field(default_factory=Sweep)

    def __post_init__(self):
        if self.friction not in ("none", "law", "own"):
            raise ValueError(f"method {self.name}: friction must be 'none', 'law' or 'own', got {self.friction!r}")
        if self.sweep.kind not in ("wide", "narrow", "gamma0", "once"):
            raise ValueError(f"method {self.name}: sweep kind must be wide, narrow, gamma0 or once")

    def make_law(self, **values: float):
        """The method's law from its parameters by name (missing ones: their numeric default); each value
        checked against its range first (``ValueError`` naming the option)."""
        known = {p.name: p for p in self.parameters}
        unknown = sorted(set(values) - set(known))
        if unknown:
            raise ValueError(f"method {self.name!r} takes {', '.join(known) or 'no parameter'}, "
                             f"got {', '.join(unknown)}")
        return self.law(**values)

    def build_rigid(self, *args, **kwargs):
        """The surface against a rigid obstacle (see ``rigid``)."""
        return resolve(self.rigid)(*args, **kwargs)

    def build_two_body(self, *args, **kwargs):
        """The two-body surfaces (see ``two_body``)."""
        if self.two_body is None:
            raise ValueError(f"method {self.name!r} does not do two deformable bodies")
        return resolve(self.two_body)(*args, **kwargs)


    def build_self(self, *args, **kwargs):
        """The surfaces of a surface against itself (see ``self_contact``)."""
        if self.self_contact is None:
            raise ValueError(f"method {self.name!r} does not do self-contact")
        return resolve(self.self_contact)(*args, **kwargs)


def resolve(target: Callable | str) -> Callable:
    """A callable, or the object named ``"module:attribute"`` (imported when first needed: a declaration names
    its surface builders without importing the surfaces)."""
    if callable(target):
        return target
    module, _, name = target.partition(":")
    return getattr(importlib.import_module(module), name)
