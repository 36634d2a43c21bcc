"""``python -m fenics_contact.app <demo> [options]``: run one of the demos by name (``--list``: their names)."""
from __future__ import annotations

import runpy
import sys
from importlib import resources

DRIVERS = ("bench", "scaling", "friction_scaling", "table")  # programs of the demos folder that are not scene demos


def demo_names() -> list[str]:
    """The demos shipped with the package (one per scene), by name."""
    folder = resources.files("fenics_contact.app") / "demos"
    return sorted(p.name[:-3] for p in folder.iterdir() if p.name.endswith(".py") and not p.name.startswith("_"))


def main(argv: list[str] | None = None) -> None:
    argv = list(sys.argv[1:] if argv is None else argv)
    names = demo_names()
    if not argv or argv[0] in ("-h", "--help", "--list"):
        print("usage: python -m fenics_contact.app <demo> [options]   (<demo> --help: its options)")
        print("demos: " + ", ".join(names))
        sys.exit(0 if argv else 2)
    if argv[0] not in names:
        print(f"error: unknown demo {argv[0]!r}; accepted: {', '.join(names)}", file=sys.stderr)
        sys.exit(2)
    sys.argv = [f"fenics_contact.app.demos.{argv[0]}", *argv[1:]]
    runpy.run_module(f"fenics_contact.app.demos.{argv[0]}", run_name="__main__", alter_sys=True)


if __name__ == "__main__":
    main()
