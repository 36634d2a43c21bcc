"""The demos: one command-line program per scene (``python -m fenics_contact.app <demo>``, or
``python demos/<demo>.py`` in a checkout). Programs, not a library: nothing to import from here."""
__all__: list = []
