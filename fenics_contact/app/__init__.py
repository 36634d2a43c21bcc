"""The application on top of the library: benchmark scenes (data plus one builder each) and their mesh
builders and gmsh geometries, the demos, the command line, the benchmark harness, checks, plots and tables.

The library (:mod:`fenics_contact`) never imports this package. ``build(name, **parameters)`` builds a scene,
``run(setup, out, ...)`` solves it and writes its output; the demos (``fenics_contact/app/demos``, also
``demos/`` at the top of a checkout) are the command-line programs.
"""
from .jitcache import find_modules_by_name

find_modules_by_name()  # FFCx's compiled forms loaded without listing its cache directory each time

from . import cli  # noqa: E402
from .run import run  # noqa: E402
from .scenes import Setup, build, scene_names  # noqa: E402

__all__ = ["Setup", "build", "cli", "run", "scene_names"]
