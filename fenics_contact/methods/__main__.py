"""``python -m fenics_contact.methods``: the registered methods as Markdown (``docs/methods.md``)."""
import sys

from . import markdown

sys.stdout.write(markdown())
