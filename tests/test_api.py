"""The public API: ``fenics_contact.__all__``, ``__all__`` in every public module, no import cycle, no gmsh on
import, a problem set up on one's own mesh with public names only, and its reference page (docs/api.md) and
docstrings."""
import ast
import importlib
import importlib.util
import inspect
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from mpi4py import MPI

import fenics_contact as fc
import fenics_contact.app as app
import fenics_contact.app.meshes  # noqa: F401  (app.meshes below)

PACKAGE = Path(fc.__file__).parent


def _modules() -> dict[str, Path]:
    """Every module of the package by dotted name (packages by their ``__init__``)."""
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _imports(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """Package modules that ``name`` imports anywhere in its source (top level, functions, TYPE_CHECKING)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            # ``from X import y``: y is a module of X, or a name defined in X
            targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base for a in node.names]
        else:
            continue
        for t in targets:
            while t and t not in modules:  # ``import a.b.c`` of a name: its innermost module
                t = t.rpartition(".")[0]
            if t and t != name:
                found.add(t)
    return found


def test_all_names_resolve():
    assert len(fc.__all__) == len(set(fc.__all__))
    missing = [n for n in fc.__all__ if not hasattr(fc, n)]
    assert not missing, missing
    for needed in ("ContactProblem", "Dirichlet", "Solver", "ConvergenceError", "make_law", "contact_surface",
                   "two_body_surfaces", "unknown", "Surface", "StepSolver", "XDMFWriter", "write_summary",
                   "LinearElastic", "HalfPlane"):
        assert needed in fc.__all__, needed
    for needed in ("build", "scene_names", "Setup", "run", "cli"):  # the application's entry points
        assert needed in app.__all__ and hasattr(app, needed), needed


def test_every_public_module_declares_all():
    """Every module (no ``_`` in its dotted name) has ``__all__``, and its names exist."""
    for name in _modules():
        if any(part.startswith("_") for part in name.split(".")) or name.startswith("fenics_contact.app.demos."):
            continue  # private, or a program (the demos)
        module = importlib.import_module(name)
        assert isinstance(getattr(module, "__all__", None), list), f"{name} has no __all__"
        missing = [n for n in module.__all__ if not hasattr(module, n)]
        assert not missing, f"{name}.__all__ names missing objects: {missing}"


def test_every_enforcement_implements_the_surface_interface():
    """The surfaces the constructors return are :class:`Surface` subclasses with every abstract hook defined."""
    for cls in (fc.ContactSurface, fc.FrictionalContact, fc.BoundContact, fc.NitscheContact, fc.MultiplierContact,
                fc.CondensedContact, fc.TwoBodySurface, fc.SegmentSurface, fc.TwoBodyMultiplier):
        assert issubclass(cls, fc.Surface) and not cls.__abstractmethods__, cls
    assert issubclass(fc.CondensedCoulomb, fc.StepSolver) and not issubclass(fc.CondensedCoulomb, fc.Surface)


def test_no_import_cycle():
    """The graph of imports between the package's modules (including imports inside functions) is acyclic."""
    modules = _modules()
    graph = {name: _imports(name, path, modules) for name, path in modules.items()}
    assert "fenics_contact.twobody.pairing" in graph["fenics_contact.mortar.surface"]  # relative imports seen
    state: dict[str, int] = {}  # 1 on the DFS stack, 2 done

    def visit(n: str, stack: list[str]) -> None:
        state[n] = 1
        for m in sorted(graph[n]):
            if state.get(m) == 1:
                cycle = stack[stack.index(m):] + [m]
                raise AssertionError("import cycle: " + " -> ".join(cycle))
            if m not in state:
                visit(m, stack + [m])
        state[n] = 2

    for n in sorted(graph):
        if n not in state:
            visit(n, [n])


def test_core_never_imports_the_application():
    """No module of the library (``fenics_contact`` outside ``fenics_contact.app``) imports a module of the
    application, anywhere in its source (top level, functions, TYPE_CHECKING)."""
    modules = _modules()
    core = {n: p for n, p in modules.items() if not (n + ".").startswith("fenics_contact.app.")}
    assert "fenics_contact.solver" in core and "fenics_contact.app.bench" not in core
    edges = [(n, m) for n, p in core.items() for m in _imports(n, p, modules)
             if (m + ".").startswith("fenics_contact.app.")]
    assert not edges, edges


def test_import_loads_no_application_module():
    """``import fenics_contact`` loads the library alone: no plotting, mesher, scene or benchmark module."""
    code = ("import sys, fenics_contact; print(sorted(m for m in sys.modules if m.split('.')[0] in "
            "('matplotlib', 'pyvista', 'gmsh') or '.bench' in m or '.scenes' in m "
            "or m.startswith('fenics_contact.app')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={k: v for k, v in __import__("os").environ.items()
                              if not k.startswith(("OMPI_", "PMIX_", "PMI_"))})
    # the last line: an MPI transport may print its own noise first (UCX in the Debian 13 root)
    assert out.returncode == 0 and out.stdout.strip().splitlines()[-1] == "[]", (out.stdout, out.stderr)


@pytest.mark.parametrize("method", ["vi", "auglag", "lagrange", "coulomb"])
def test_own_mesh_with_public_names(method):
    """A block on a rigid plate, set up from public names only on a dolfinx mesh of one's own: top moved down by
    d, horizontal motion free, frictionless base. Uniform plane-strain state: p = E/(1 - nu^2) d/H."""
    from dolfinx import fem
    from dolfinx import mesh as dmesh

    E, nu, H, d = 1000.0, 0.3, 2.0, 0.32
    mesh = dmesh.create_rectangle(MPI.COMM_WORLD, [np.zeros(2), np.array([1.0, H])], [3, 6])
    fdim = mesh.topology.dim - 1
    sides = {1: lambda x: np.isclose(x[1], 0.0), 2: lambda x: np.isclose(x[1], H), 3: lambda x: np.isclose(x[0], 0)}
    facets = [(tag, dmesh.locate_entities_boundary(mesh, fdim, where)) for tag, where in sides.items()]
    indices = np.concatenate([f for _, f in facets]).astype(np.int32)
    values = np.concatenate([np.full(len(f), tag, np.int32) for tag, f in facets])
    order = np.argsort(indices)
    tags = dmesh.meshtags(mesh, fdim, indices[order], values[order])

    law = fc.make_law(method, **({"K": 1e3} if method == "auglag" else {}))
    u, V = fc.unknown(mesh, 1, law)
    load = fem.Constant(mesh, 0.0)
    contact = fc.contact_surface(u, tags, 1, fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load)
    bcs = [fc.Dirichlet.on_facets(V, tags, 2, 1, -d), fc.Dirichlet.on_facets(V, tags, 3, 0)]
    problem = fc.ContactProblem(u, fc.LinearElastic(E, nu), load, bcs, [contact],
                                step_solver=fc.step_solver_for([contact]))
    fc.Solver(problem, quiet=True, augment_max=30, augment_tol=1e-10).run([1.0])
    exact = E / (1 - nu**2) * d / H
    pressure = (contact.friction_profile()["pressure"].mean() if method == "coulomb"
                else contact.mean_pressure())
    assert pressure == pytest.approx(exact, rel=1e-8)


def test_coulomb_takes_its_step_solver():
    """A surface that needs a step solver (method ``coulomb``) gets it from the problem without being told; two
    such surfaces in one problem are refused before any solve, naming them."""
    from dolfinx import fem

    mesh, _, tags = app.meshes.rectangle(MPI.COMM_WORLD, 1.0, 1.0, 2, 2)
    u = fem.Function(fc.function_space(mesh, "Lagrange", 1, (2,)))
    load = fem.Constant(mesh, 0.0)
    contacts = [fc.contact_surface(u, tags, side, fc.HalfPlane([0.0, y], [0.0, 1.0 - 2 * y]), fc.ExactCoulomb(0.3),
                                   load, name=side) for side, y in (("bottom", 0.0), ("top", 1.0))]
    problem = fc.ContactProblem(u, fc.LinearElastic(1.0, 0.3), load, [], contacts[:1])
    assert isinstance(problem.step_solver, fc.CondensedCoulomb)
    with pytest.raises(ValueError, match="condenses one contact surface, got 2: bottom, top"):
        fc.ContactProblem(u, fc.LinearElastic(1.0, 0.3), load, [], contacts)


def test_problem_residual_and_jacobian_are_public(tangent_check):
    """``ContactProblem.F`` / ``J`` (dolfinx's NonlinearProblem signatures) at a state: the Jacobian matches a
    central difference of the residual (penalty law, closed contact)."""
    setup = app.build("block", law=fc.make_law("penalty", K=1e4))
    problem = setup.problem
    solver = fc.Solver(problem, quiet=True)
    solver.run(setup.loads)
    x = problem.create_vector()
    x.array[:] = problem.u.x.array[: len(x.array)]
    d = x.duplicate()
    d.setRandom()
    Jd, fd = tangent_check(solver, x, d, 1e-6, lambda c: np.zeros(0))  # a rigid obstacle: no pairing
    assert (fd - Jd).norm() <= 1e-6 * Jd.norm()


def test_demos_import_public_names_only():
    """Every ``from fenics_contact[.module] import name`` in the demos (anywhere in the file) names a public
    module's ``__all__`` entry or a public submodule."""
    for path in sorted((PACKAGE / "app" / "demos").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("fenics_contact"):
                assert not any(p.startswith("_") for p in node.module.split(".")), (path.name, node.module)
                module = importlib.import_module(node.module)
                for a in node.names:
                    sub = f"{node.module}.{a.name}"
                    public = a.name in module.__all__ or (
                        not a.name.startswith("_") and importlib.util.find_spec(sub) is not None)
                    assert public, f"{path.name}: {sub} is not public"
            elif isinstance(node, ast.Import):
                for a in node.names:
                    assert not any(p.startswith("_") for p in a.name.split(".")), (path.name, a.name)


@pytest.mark.parametrize("old,new", [("Exact", "SnesVI"), ("Coulomb", "ExactCoulomb"), ("NitscheLaw", "Nitsche")])
def test_former_names_warn_and_give_the_new_class(old, new):
    """The renamed laws keep their former names for one release: the same class, with a DeprecationWarning."""
    for module in (fc, fc.laws):
        with pytest.warns(DeprecationWarning, match=new):
            assert getattr(module, old) is getattr(fc, new)


def test_a_method_without_a_law_of_the_gap_is_no_contact_law():
    """vi, coulomb, the multipliers and Nitsche are formulations, not laws of the gap: they have no force to call,
    and friction on top of them is refused but for Nitsche's and the multipliers' (their own tangential terms)."""
    for formulation in (fc.SnesVI(), fc.ExactCoulomb(0.3), fc.LagrangeMultiplier(), fc.Nitsche()):
        assert isinstance(formulation, fc.Formulation) and not isinstance(formulation, fc.ContactLaw)
        assert not hasattr(formulation, "force")
        if isinstance(formulation, (fc.Nitsche, fc.LagrangeMultiplier)):
            law = fc.Friction(formulation, mu=0.3)
            assert law.has_friction and law.method == formulation.name
            continue
        with pytest.raises(ValueError, match="friction needs a normal law"):
            fc.Friction(formulation, mu=0.3)
    assert isinstance(fc.Penalty(1.0), fc.Formulation)


def test_layout_page_is_the_modules_docstrings():
    """docs/layout.md is what the modules' docstrings say (``make docs`` writes it with scripts/layout.py)."""
    spec = importlib.util.spec_from_file_location("layout", PACKAGE.parent / "scripts" / "layout.py")
    layout = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(layout)
    assert (PACKAGE.parent / "docs" / "layout.md").read_text() == layout.page()



def test_no_class_of_the_library_is_a_god_class():
    """Every class of the library (not the application) fits in about 250 lines (one job each), or says in its
    docstring why it does not."""
    long = []
    for path in PACKAGE.rglob("*.py"):
        if "app" in path.relative_to(PACKAGE).parts:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ClassDef) and node.end_lineno - node.lineno + 1 > 250 and \
                    "Why one class of this size" not in (ast.get_docstring(node) or ""):
                long.append(f"{path.relative_to(PACKAGE)}:{node.name} ({node.end_lineno - node.lineno + 1} lines)")
    assert not long, long


def test_the_solver_destroys_what_it_owns():
    """``with Solver(...)``: the SNES, its matrix and vectors are destroyed on leaving the block (PETSc objects
    destroyed by their owner, collectively), after a solve that gave the closed form."""
    setup = app.build("block", law=fc.make_law("penalty", K=1e4))
    with fc.Solver(setup.problem, quiet=True) as solver:
        solver.run(setup.loads)
        snes, A, b = solver.snes, solver.A, solver.b
        assert snes.handle and A.handle and b.handle
    assert not snes.handle and not A.handle and not b.handle
    E, nu = 1000.0, 0.3
    K = 1e4  # the penalty's penetration p / K: the homogeneous state with it
    exact = E / (1 - nu**2) * 0.32 / (2.0 + E / (1 - nu**2) / K)
    assert setup.figures()["contact_pressure"] == pytest.approx(exact, rel=1e-8)


def _kind(obj) -> str:
    """The autodoc directive that documents ``obj``."""
    if inspect.ismodule(obj):
        return "module"
    if inspect.isclass(obj):
        return "exception" if issubclass(obj, BaseException) else "class"
    return "function" if inspect.isfunction(obj) else "data"


def test_api_page_documents_every_public_name():
    """docs/api.md (the API reference of ``make docs``) has one autodoc directive of the right kind for every name
    of ``fc.__all__``, and none for a name outside it."""
    page = (PACKAGE.parent / "docs" / "api.md").read_text()
    directives = re.findall(r"^\.\. auto(\w+):: fenics_contact\.(\w+)\s*$", page, re.M)
    names = [name for _, name in directives]
    assert len(names) == len(set(names)), sorted(n for n in names if names.count(n) > 1)
    assert sorted(names) == sorted(fc.__all__), sorted(set(names) ^ set(fc.__all__))
    wrong = [(name, kind) for kind, name in directives if kind != _kind(getattr(fc, name))]
    assert not wrong, wrong


def _args_section(doc: str) -> "list[str] | None":
    """The names of a Google-style ``Args:`` section (``name: ...`` or ``name (type): ...``), or None without one."""
    match = re.search(r"^Args:\n((?:[ \t]+\S.*\n?|[ \t]*\n)+)", doc, re.M)
    if match is None:
        return None
    lines = [line for line in match.group(1).splitlines() if line.strip()]
    indent = min(len(line) - len(line.lstrip()) for line in lines)
    return [re.split(r"[\s(:]", line.strip(), maxsplit=1)[0].lstrip("*") for line in lines
            if len(line) - len(line.lstrip()) == indent]


def test_public_classes_and_functions_have_docstrings():
    """Every class and function of ``fc.__all__`` has a docstring of its own; one with an ``Args:`` section (its
    own or one of its public methods') names every parameter there, and only those."""
    missing, wrong = [], []
    for name in fc.__all__:
        obj = getattr(fc, name)
        if not (inspect.isclass(obj) or inspect.isfunction(obj)):
            continue
        doc = obj.__doc__ or ""
        if not doc.strip() or doc.startswith(f"{name}("):  # none, or the signature a dataclass writes
            missing.append(name)
        callables = [(name, obj)]
        for member, value in (vars(obj).items() if inspect.isclass(obj) else ()):
            value = value.__func__ if isinstance(value, (staticmethod, classmethod)) else value
            if not member.startswith("_") and inspect.isfunction(value):
                callables.append((f"{name}.{member}", value))
        for label, f in callables:
            documented = _args_section(inspect.getdoc(f) or "")
            if documented is None:
                continue
            params = list(inspect.signature(f).parameters)
            if label != name and params[:1] in (["self"], ["cls"]):  # a method's own object, not an argument
                params = params[1:]
            if sorted(documented) != sorted(params):
                wrong.append(f"{label}: Args {documented}, parameters {params}")
    assert not missing, f"no docstring: {missing}"
    assert not wrong, wrong


def _own_args(obj) -> "list[str] | None":
    """The ``Args:`` names of a class (its docstring or its ``__init__``'s) or a function, None without one."""
    found = _args_section(inspect.getdoc(obj) or "")
    init = vars(obj).get("__init__") if inspect.isclass(obj) else None
    if found is None and init is not None:
        found = _args_section(inspect.getdoc(init) or "")
    return found


def test_every_public_callable_documents_its_arguments():
    """Every class and function of ``fc.__all__`` that takes arguments has an ``Args:`` section naming each of
    them (a class: its docstring or its ``__init__``'s), and every function that returns something a
    ``Returns:`` section."""
    missing, returns = [], []
    for name in fc.__all__:
        obj = getattr(fc, name)
        if not (inspect.isclass(obj) or inspect.isfunction(obj)):
            continue
        try:
            params = list(inspect.signature(obj).parameters)  # a class's: its constructor's, without self
        except (TypeError, ValueError):  # a class without an introspectable constructor takes no arguments here
            params = []
        documented = _own_args(obj)
        if params and (documented is None or sorted(documented) != sorted(params)):
            missing.append(f"{name}: Args {documented}, parameters {params}")
        if inspect.isfunction(obj) and inspect.signature(obj).return_annotation not in (None, "None",
                                                                                        inspect.Signature.empty):
            if not re.search(r"^Returns:", inspect.getdoc(obj) or "", re.M):
                returns.append(name)
    assert not missing, missing
    assert not returns, f"no Returns section: {returns}"


def test_every_public_constant_has_a_described_entry():
    """A module-level constant of ``fc.__all__`` (not a class, function or module) has an ``autodata`` entry in
    docs/api.md with a paragraph of its own that says what it holds."""
    page = (PACKAGE.parent / "docs" / "api.md").read_text()
    constants = [n for n in fc.__all__ if _kind(getattr(fc, n)) == "data"]
    assert "MODELS" in constants and "LINEAR_SOLVERS" in constants
    bare = []
    for name in constants:
        entry = re.search(rf"^\.\. autodata:: fenics_contact\.{name}\n((?:   .*\n|\n)*)", page, re.M)
        text = [line.strip() for line in (entry.group(1) if entry else "").splitlines()
                if line.strip() and not line.strip().startswith(":")]
        if len(" ".join(text).split()) < 5:
            bare.append(name)
    assert not bare, f"no description in docs/api.md: {bare}"
