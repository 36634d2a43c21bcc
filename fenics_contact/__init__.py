"""fenics_contact: contact mechanics in FEniCSx (dolfinx), as a library.

Set up a contact problem on your own mesh with ``import fenics_contact as fc`` (``mesh`` and ``facets`` from
dolfinx or :func:`read_gmsh`, facets named ``"base"``, ``"top"`` and ``"left"``; ``tests/test_api.py`` has a
complete, tested example)::

    law = fc.make_law("auglag", K=1e5)                      # or fc.Penalty(1e5), fc.SnesVI(), fc.ExactCoulomb(0.3)
    u, V = fc.unknown(mesh, 1, law)                          # the unknown (mixed for method lagrange)
    load = dolfinx.fem.Constant(mesh, 0.0)                   # the load parameter t
    contact = fc.contact_surface(u, facets, "base", fc.HalfPlane([0, 0], [0, 1]), law, load)
    problem = fc.ContactProblem(u, fc.LinearElastic(1000.0, 0.3), load,
                                [fc.Dirichlet.on_facets(V, facets, "top", 1, -0.1),  # u_y = -0.1 t
                                 fc.Dirichlet.on_facets(V, facets, "left", 0)], [contact])  # u_x = 0
    fc.Solver(problem, augment_max=10).run([0.5, 1.0])
    contact.mean_pressure()

Every contact enforcement implements :class:`Surface` (the hooks the solver calls, declared once);
a :class:`StepSolver` solves whole load steps instead of SNES (method ``coulomb``; the problem takes the
one its surface needs). Output:
:class:`XDMFWriter`, :func:`write_summary`; read back without dolfinx: :func:`read_xdmf`. Importing the package
imports neither gmsh nor the application (:mod:`fenics_contact.app`: the benchmark scenes, demos, command line,
plots and tables, built on this API).
"""
from . import capabilities, cells, compat, domain, failure, jitlog, kinematics, laws, methods, search
from .bounds import BoundContact
from .capabilities import UnsupportedCombination
from .cells import MeshError, check_cells
from .compat import function_space, interpolate_expression
from .condensed import CondensedContact, CondensedCoulomb, CondensedTwoBody, CondensedTwoBodyCoulomb, step_solver_for
from .contact import ContactSurface, contact_measure
from .domain import NamedTags, read_gmsh, tag_boundary
from .factory import contact_surface, two_body_multipliers, two_body_surfaces
from .friction import Friction, FrictionalContact
from .incompressible import Kinematics, MixedLinearElastic, MixedNeoHookean
from .laws import (
    AugmentedLagrangian,
    ContactLaw,
    CrossConstraints,
    ExactCoulomb,
    Formulation,
    LagrangeMultiplier,
    Nitsche,
    NormalCompliance,
    Penalty,
    PenaltyMultiplier,
    SnesVI,
)
from .materials import PLANES, LinearElastic, Material, Materials, NeoHookean, lame
from .methods import METHODS, Method, Parameter, Sweep, make_law, register
from .models import MODELS
from .mortar import SegmentSurface
from .multipliers import MultiplierContact, TwoBodyMultiplier, unknown
from .nitsche import NitscheContact
from .obstacles import Ball, Cylinder, HalfPlane, Obstacle, Sphere
from .output import XDMFWriter, write_summary
from .problem import ContactProblem, Dirichlet, Stabilised
from .reading import XDMFSeries, read_xdmf
from .solver import INEXACT_NEWTON, LINEAR_SOLVERS, ConvergenceError, Solver, StepRecord
from .surface import StepSolver, Surface
from .twobody import TwoBodySurface
from .twobody_friction import FrictionalTwoBodySurface

__all__ = [
    # materials
    "Material", "LinearElastic", "NeoHookean", "MixedNeoHookean", "MixedLinearElastic",
    "Kinematics", "Materials", "MODELS", "PLANES", "lame", "kinematics",
    # contact laws (method name -> class: METHODS, make_law)
    "Formulation", "ContactLaw", "Penalty", "CrossConstraints", "AugmentedLagrangian", "NormalCompliance", "SnesVI",
    "ExactCoulomb", "LagrangeMultiplier", "PenaltyMultiplier", "Nitsche", "Friction",
    # the method registry (one declaration per method: law, parameters, surfaces, capability rules, benchmark)
    "METHODS", "make_law", "Method", "Parameter", "Sweep", "register",
    # rigid obstacles
    "Obstacle", "HalfPlane", "Ball", "Cylinder", "Sphere",
    # contact surfaces: the interface, the constructors, the enforcements
    "Surface", "StepSolver", "contact_surface", "two_body_surfaces", "two_body_multipliers", "unknown",
    "step_solver_for", "contact_measure", "ContactSurface", "FrictionalContact", "BoundContact", "NitscheContact",
    "MultiplierContact", "CondensedContact", "CondensedCoulomb", "CondensedTwoBody",
    "CondensedTwoBodyCoulomb", "TwoBodySurface", "SegmentSurface",
    "TwoBodyMultiplier", "FrictionalTwoBodySurface",
    # your own mesh: gmsh physical names
    "read_gmsh", "NamedTags", "tag_boundary", "check_cells", "MeshError",
    # problem, boundary conditions, solver
    "ContactProblem", "Dirichlet", "Stabilised", "Solver", "StepRecord", "ConvergenceError", "LINEAR_SOLVERS",
    "INEXACT_NEWTON",
    # spaces (the same call on every supported dolfinx)
    "function_space", "interpolate_expression",
    # output
    "XDMFWriter", "write_summary", "read_xdmf", "XDMFSeries",
    # the capability matrix: a refused combination of options (capabilities.check, docs/capabilities.md)
    "UnsupportedCombination",
    # public submodules
    "capabilities", "cells", "compat", "domain", "failure", "methods", "search",
]

# Former names, kept for one release: each use warns (DeprecationWarning) and gives the new object.
_DEPRECATED = {**{old: ("laws", new) for old, new in laws.DEPRECATED.items()}}


def __getattr__(name: str):
    if name in _DEPRECATED:
        import warnings

        module, new = _DEPRECATED[name]
        warnings.warn(f"fenics_contact.{name} is deprecated: use fenics_contact.{new}", DeprecationWarning,
                      stacklevel=2)
        return globals()[new]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


jitlog.quiet_compiler()  # the form compiler's build commands kept out of a script's INFO log
