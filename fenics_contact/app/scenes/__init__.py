"""Benchmark scenes: data plus one builder each, shared by demos, tests and benchmarks.

A builder returns a :class:`Setup`; ``figures()`` returns the scene's figures
(reduced over all ranks) after a solve. A builder refuses a mesh size the machine's memory cannot hold before
any work (:func:`refuse_size`, :class:`SizeError`). Each scene module declares its builder's numeric
parameters in ``OPTIONS`` (:class:`Option`: help text with units, accepted range, options it excludes or
needs), from which :func:`add_scene_options` makes the demos' range-checked command-line options.
"""
from __future__ import annotations

import argparse
import gc
import importlib
import inspect
import logging
import math
import pkgutil
import re
import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

from dolfinx import fem
from mpi4py import MPI

from ...cells import MeshError
from ...condensed import operator
from ...condensed.operator import CondensedTooLarge
from ...friction import Friction
from ...laws import ExactCoulomb, LagrangeMultiplier
from ...problem import DIRICHLET_WEIGHT, ContactProblem, Stabilised
from ...surface import Surface
from ..cli import GIVEN, UsageError  # GIVEN, Option.needs: the other option must be given (any value)
from ..memory import BYTES_PER_DOF, available_memory, gigabytes, machine_memory

__all__ = ["Setup", "scene_names", "build", "Stabilised", "positive", "nonnegative", "poisson", "numeric_parameters",
           "Option", "GIVEN", "LIMIT", "unit", "scene_options", "add_scene_options", "scene_arguments", "SizeError",
           "max_dofs", "log_dofs", "refuse_size", "refuse_fine", "refuse_count", "refuse_refined",
           "scale_alart_curnier", "SPARSE_C"]


@dataclass
class Setup:
    """What a scene builder returns."""

    name: str
    problem: ContactProblem
    contacts: list[Surface]
    loads: Sequence[float]
    parameters: dict
    figures: Callable[[], dict]
    fields: list[fem.Function] = field(default_factory=list)
    build_time_s: float = 0.0  # mesh, spaces and form compilation (max over ranks)

    @property
    def displacement(self) -> fem.Function:
        """The displacement Function (``fields[0]``; a collapsed copy when the unknown is mixed)."""
        return self.fields[0]

    @property
    def dofs(self) -> int:
        """Global number of unknowns: with multipliers, the displacement and the pressures on the contact
        surfaces (the pressure dofs pinned to 0 off the surfaces are not counted, see :mod:`multipliers`)."""
        V = self.problem.u.function_space
        pinned = sum(c.pinned_dofs for c in self.contacts)
        return V.dofmap.index_map.size_global * V.dofmap.index_map_bs - pinned


def scene_names() -> list[str]:
    """Every scene module of this package (each defines ``build``)."""
    return sorted(m.name for m in pkgutil.iter_modules(__path__) if not m.name.startswith("_"))


logger = logging.getLogger(__name__)

# The sparse exact method's Alart-Curnier c where the condensed method is too large: this fraction of E / h, from the
# problem's own stiffness (the mean diagonal, ~ E h^(d-2)) and the contact's mean vertex spacing (steers Newton only).
SPARSE_C = 0.1


def scale_alart_curnier(setup: Setup) -> float | None:
    """Set the Alart-Curnier ``c`` of the setup's frictional multiplier surfaces (method ``lagrange`` with friction)
    to :data:`SPARSE_C` times the problem's mean diagonal stiffness over the contact's area per vertex (pressure per
    length, ~ ``E / h``: the same Newton path in any consistent units and on any mesh). Returns ``c``, or None
    if the setup has no such surface. Collective."""
    contacts = [c for c in setup.contacts if isinstance(getattr(c, "law", None), Friction)
                and isinstance(c.law.normal, LagrangeMultiplier) and "c" in getattr(c, "constants", {})]
    if not contacts:
        return None
    points = sum(len(c.point_values()[0]) for c in contacts)  # every rank's (collective)
    area = sum(c.area() for c in contacts)
    diagonal = setup.problem.stiffness / DIRICHLET_WEIGHT  # the bodies' mean diagonal stiffness
    c = SPARSE_C * diagonal * points / max(area, 1e-300)
    for contact in contacts:
        contact.constants["c"].value = c
    return c


def _sparse_instead(builder: Callable, kwargs: dict, exc: CondensedTooLarge) -> Setup:
    """The scene with method ``lagrange`` with friction (the sparse exact method, the same discrete Coulomb problem)
    where method ``coulomb``'s condensed system is too large; says so in one line."""
    law = kwargs.get("law")
    if not isinstance(law, ExactCoulomb):
        raise exc
    comm = kwargs.get("comm", MPI.COMM_WORLD)
    setup = builder(**{**kwargs, "law": Friction(LagrangeMultiplier(1.0), mu=law.mu)})
    c = scale_alart_curnier(setup)
    if comm.rank == 0:
        logger.warning("method coulomb: %d contact dofs, more than its dense condensed system's %d: solved by the "
                       "sparse exact method instead (method lagrange with friction, Alart-Curnier c = %.3g)",
                       exc.n_c, operator.MAX_CONDENSED, c)
    setup.parameters = {**setup.parameters, "solved_by": "lagrange (sparse exact Coulomb)",
                        "condensed_contact_dofs": exc.n_c}
    return setup


def build(name: str, **kwargs) -> Setup:
    """Build scene ``name`` (see :func:`scene_names`) with keyword arguments of its builder."""
    if name not in scene_names():
        raise ValueError(f"unknown scene {name!r}; accepted: {', '.join(scene_names())}")
    b = importlib.import_module(f"{__name__}.{name}").build
    start = time.perf_counter()
    try:
        too_large = None
        try:
            setup = b(**kwargs)
        except CondensedTooLarge as exc:
            too_large = exc.with_traceback(None)  # its frames hold the condensed scene: freed before the next
        if too_large is not None:  # the same exact Coulomb problem on the sparse system
            gc.collect()  # (dolfinx's objects refer to each other)
            setup = _sparse_instead(b, kwargs, too_large)
    except MeshError as exc:  # the user gave no mesh: the options that made it are at fault
        raise _mesh_from_options(b, kwargs, exc) from None
    comm = setup.problem.comm
    setup.build_time_s = comm.allreduce(time.perf_counter() - start, op=MPI.MAX)
    return setup


def _mesh_from_options(builder: Callable, kwargs: dict, exc: MeshError) -> UsageError:
    """The error of a scene whose mesh, made from its options, has cells it cannot be solved on (``exc``): naming the
    dimensional options given (those other than the builder's defaults), not asking to fix a mesh the user did not
    give (a ``ValueError``; a bad command line for the demos)."""
    defaults = numeric_parameters(builder)
    options = scene_options(builder)
    given = [f"{_flag(n)} {v:g}" for n, v in kwargs.items() if n in defaults and isinstance(v, (int, float))
             and v != defaults[n] and unit(options[n]) is not None]
    what = re.sub(r"^.*? has ", "", str(exc)).removesuffix(": fix the mesh")
    return UsageError(f"the scene's mesh made from {', '.join(given) if given else 'its options'} has {what}: lengths "
                      "that far apart (or a mesh that fine) are beyond floating point's resolution; give them closer "
                      "to each other")


def positive(**values: float | None) -> None:
    """``ValueError`` naming the first of ``values`` that is not a finite number > 0 (``None``: a default)."""
    for name, v in values.items():
        if v is not None and not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {v!r}")


def nonnegative(**values: float | None) -> None:
    """``ValueError`` naming the first of ``values`` that is not a finite number >= 0 (``None``: a default)."""
    for name, v in values.items():
        if v is not None and not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
            raise ValueError(f"{name} must be a finite number >= 0, got {v!r}")


def poisson(**values: float | None) -> None:
    """``ValueError`` naming the first Poisson's ratio of ``values`` outside ``[0, 0.5)`` (``None``: a default)."""
    for name, v in values.items():
        if v is not None and not (isinstance(v, (int, float)) and 0.0 <= v < 0.5):
            raise ValueError(f"{name} must be in [0, 0.5), got {v!r}")


def numeric_parameters(builder: Callable) -> dict[str, float | None]:
    """The keyword arguments of a scene builder that are physical numbers (annotated ``float``, or
    ``float | None``: ``None`` is a default derived from the others), with their defaults."""
    out = {}
    for name, par in inspect.signature(builder).parameters.items():
        note = par.annotation if isinstance(par.annotation, str) else getattr(par.annotation, "__name__", "")
        if note in ("float", "float | None") and (par.default is None or isinstance(par.default, (int, float))):
            out[name] = par.default
    return out


@dataclass(frozen=True)
class Option:
    """A scene builder's numeric parameter as a command-line option.

    ``help``: what it is, with its units (consistent units: "length", "stress" = force / length^2, ...) and,
    for a default derived from the others (``None`` in the builder), how it is derived. ``range``: ``positive``
    (> 0), ``nonnegative`` (>= 0), ``poisson`` ([0, 0.5)) or a closed interval ``(low, high)``. ``excludes``:
    another parameter that contradicts this one (giving both is refused). ``needs``: ``(other, value)``, this
    one is used only when the demo's option ``other`` has ``value`` (:data:`GIVEN`: is given). ``below``: the
    parameters this one must be smaller than (a radius inside another)."""

    help: str
    range: str | tuple = "positive"
    excludes: str | None = None
    needs: tuple[str, object] | None = None
    below: tuple[str, ...] = ()


# A scene's numeric options (a length, a stress, a force, a factor) lie within [1 / LIMIT, LIMIT] in magnitude: the
# products of a few of them that a run forms (areas and volumes, a modulus times a volume, a penalty E / h) then stay
# within floating point's range (1e308) and above its smallest normal number.
LIMIT = 1e50
_UNIT = re.compile(r"\((length|stress|force)[;), /]")


def unit(option: Option) -> str | None:
    """The unit an option's help states (``length``, ``stress``, ``force``), or None (dimensionless)."""
    found = _UNIT.search(option.help)
    return found.group(1) if found else None


def _check_scales(options: dict[str, Option], args: argparse.Namespace) -> None:
    """:class:`~fenics_contact.app.cli.UsageError` naming the first numeric option out of ``[1 / LIMIT, LIMIT]`` in
    magnitude (overflow above, underflow below; 0 where its range allows it is not checked)."""
    from ..cli import UsageError

    for name, option in options.items():
        v = getattr(args, name, None)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or v == 0 or 1 / LIMIT <= abs(v) <= LIMIT:
            continue
        what = "overflow" if abs(v) > LIMIT else "underflow"
        kind = f"a {unit(option)}" if unit(option) else "a factor"
        raise UsageError(f"{_flag(name)} {v:g}: {what}: {kind} beyond floating point's range for the scene's products "
                         f"of it (areas, volumes, stiffnesses); accepted: {_flag(name)} of magnitude in "
                         f"[{1 / LIMIT:g}, {LIMIT:g}]")


def _option_type(range_: str | tuple[float, float]) -> Callable[[str], float]:
    from ..cli import NONNEGATIVE, POSITIVE, number

    if isinstance(range_, tuple):
        return number(float, *range_)
    return {"positive": POSITIVE, "nonnegative": NONNEGATIVE,
            "poisson": number(float, 0.0, 0.5, high_open=True)}[range_]


def scene_options(builder: Callable) -> dict[str, Option]:
    """The :class:`Option` of every numeric parameter of ``builder`` (:func:`numeric_parameters`), from its
    module's ``OPTIONS``; ``ValueError`` naming a parameter without one, or an ``OPTIONS`` entry that is not a
    parameter."""
    module = inspect.getmodule(builder)
    declared = getattr(module, "OPTIONS", {})
    params = numeric_parameters(builder)
    missing = [n for n in params if n not in declared]
    extra = [n for n in declared if n not in params]
    if missing or extra:
        raise ValueError(f"{module.__name__}.OPTIONS: " + "; ".join(
            ([f"no help text for {', '.join(missing)}"] if missing else [])
            + ([f"not parameters of build: {', '.join(extra)}"] if extra else [])))
    return {n: declared[n] for n in params}


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def add_scene_options(parser: argparse.ArgumentParser, builder: Callable, shared: Sequence[str] = ()) -> list[str]:
    """One ``--name`` option (``_`` written ``-``) per numeric keyword argument of ``builder``
    (:func:`scene_options`), range-checked when parsed, with its help text and default; returns their names.
    Two options one of which ``excludes`` the other are mutually exclusive; an option that ``needs`` another's
    value is refused without it, one not ``below`` the others it must be below is refused (checked when parsed,
    :class:`cli.StrictParser`).

    Args:
        parser: the demo's parser.
        builder: the scene's builder.
        shared: keywords of ``builder`` that the parser already has as options of the same meaning (given to the
            builder from those); any other keyword the parser already has is a ``ValueError`` (one option would
            silently set another quantity).
    """
    options = scene_options(builder)
    names: list[str] = []
    groups: dict[str, argparse._MutuallyExclusiveGroup] = {}
    for name in numeric_parameters(builder):  # before adding any: a refused call leaves the parser as it was
        flag = _flag(name)
        if flag in parser._option_string_actions and name not in shared:
            raise ValueError(f"scene option {flag} of {builder.__module__} is already an option of the demo "
                             f"({parser._option_string_actions[flag].help}); rename one, or name it in shared")
    for name, default in numeric_parameters(builder).items():
        flag = _flag(name)
        if flag in parser._option_string_actions:
            continue
        opt = options[name]
        if opt.excludes is not None and opt.excludes not in groups:
            groups[name] = groups[opt.excludes] = parser.add_mutually_exclusive_group()
        where = groups.get(name, parser)
        where.add_argument(flag, type=_option_type(opt.range), default=default, dest=name, help=opt.help)
        names.append(name)
        if opt.needs is not None and hasattr(parser, "requirements"):
            parser.requirements.append((name, *opt.needs))
        if hasattr(parser, "orders"):
            parser.orders.extend((name, other) for other in opt.below)
    if hasattr(parser, "checks"):
        parser.checks.append(lambda args: _check_scales(options, args))
    return names


def scene_arguments(args: argparse.Namespace, names: Sequence[str]) -> dict:
    """The values of the options :func:`add_scene_options` added, as keyword arguments of the builder."""
    return {n: getattr(args, n) for n in names}


# --- sizes the machine can hold --------------------------------------------------------------------------------
def max_dofs(comm: MPI.Comm) -> tuple[float, str]:
    """The most unknowns a run on ``comm`` can hold (:data:`BYTES_PER_DOF` each, in the memory of all its ranks,
    at most the machine's), and the phrase of :func:`available_memory` naming the limit. Collective."""
    nbytes, phrase = available_memory()
    machine = machine_memory()
    total = comm.allreduce(nbytes, op=MPI.SUM)
    if total >= machine:
        return machine / BYTES_PER_DOF, f"this machine's {gigabytes(machine)}"
    return total / BYTES_PER_DOF, phrase if comm.size == 1 else f"{comm.size} ranks x {phrase}"


class SizeError(UsageError):
    """A mesh the machine's memory cannot hold: the builder argument ``parameter`` (the demos' option
    ``--parameter``), its ``value``, ``reason`` (the estimate against the memory) and ``accepted`` (the values
    that fit, e.g. ``"0 to 6"``). A ``ValueError``; the demos' option out of its range, a bad command line (exit
    status 2), as a count beyond the memory is when parsed."""

    def __init__(self, parameter: str, value, reason: str, accepted: str):
        self.parameter, self.value, self.reason, self.accepted = parameter, value, reason, accepted
        super().__init__(f"{parameter} = {value!r}: {reason}; accepted {parameter}: {accepted}")


def refuse_size(parameter: str, value, log10_dofs: float, accepted: Callable[[float], str], comm: MPI.Comm) -> None:
    """Raise :class:`SizeError` if ``10**log10_dofs`` unknowns (a scene's lower estimate for ``parameter =
    value``) cannot fit in the memory of the run on ``comm`` (:func:`max_dofs`); ``accepted(log10 of the most
    unknowns)``: the values of ``parameter`` that fit, for the message. Collective."""
    most, phrase = max_dofs(comm)
    if log10_dofs <= math.log10(most):
        return
    dofs = f"{10 ** log10_dofs:.2g}" if log10_dofs < 15 else f"1e{log10_dofs:.0f}"
    need = gigabytes(10 ** log10_dofs * BYTES_PER_DOF) if log10_dofs < 15 else \
        f"1e{log10_dofs + math.log10(BYTES_PER_DOF) - 9:.0f} GB"
    raise SizeError(parameter, value, f"about {dofs} unknowns, at least {need} of memory, more than {phrase}",
                    accepted(math.log10(most)))


def log_dofs(*terms: tuple[float, float, float]) -> float:
    """``log10`` of a scene's lower estimate of its unknowns, ``sum(c (L / h)^d)`` over ``terms`` ``(c, L / h, d)``:
    ``c`` unknowns per cell-sized cube of a zone of extent ``L`` meshed at size ``h`` in ``d`` dimensions (computed
    in logarithms: no overflow at any size)."""
    logs = [math.log10(c) + d * math.log10(ratio) for c, ratio, d in terms]
    top = max(logs)
    return top + math.log10(sum(10 ** (v - top) for v in logs))


def refuse_fine(parameter: str, value: float, log10_dofs: float, power: float, comm: MPI.Comm) -> None:
    """:func:`refuse_size` of a mesh size ``value`` (the builder argument ``parameter``) of which the unknowns, about
    ``10**log10_dofs``, go as ``value**-power``: the accepted sizes are those from the one that fits. Collective."""
    refuse_size(parameter, value, log10_dofs, lambda most: f">= {value * 10 ** ((log10_dofs - most) / power):.3g}",
                comm)


def refuse_count(parameter: str, value: int, log10_dofs: float, power: float, comm: MPI.Comm, low: int = 1) -> None:
    """:func:`refuse_size` of a count of cells ``value`` (the builder argument ``parameter``) of which the unknowns,
    about ``10**log10_dofs``, go as ``value**power``: the accepted counts are those up to the one that fits.
    Collective."""
    refuse_size(parameter, value, log10_dofs, lambda most: f"{low} to "
                f"{max(low, math.floor(value * 10 ** ((most - log10_dofs) / power)))}", comm)


def refuse_refined(parameter: str, size: float, refinement: int, log10_dofs: float, power: float, per_level: float,
                   comm: MPI.Comm) -> None:
    """:func:`refuse_size` of a mesh of size ``size`` (builder argument ``parameter``) refined ``refinement`` times,
    about ``10**log10_dofs`` unknowns (``x 10**per_level`` per refinement, as ``size**-power``): the refinement is
    named if there is one, else the size. Collective."""
    if int(refinement) <= 0:
        refuse_fine(parameter, size, log10_dofs, power, comm)
        return
    base = log10_dofs - per_level * int(refinement)
    refuse_size("refinement", refinement, log10_dofs, lambda most: f"0 to {math.floor((most - base) / per_level)}"
                if most >= base else f"none with {parameter} {size:g}", comm)
