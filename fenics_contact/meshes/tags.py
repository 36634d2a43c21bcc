"""Physical tags of the meshes (cells and facets), and name -> tag maps for ``check_tags``."""

__all__ = [
    "DOMAIN", "CONTACT", "SYMMETRY", "TOP", "FREE", "BOTTOM", "RIGHT", "RECT_TOP", "LEFT", "SYMMETRY_Y", "END",
    "CYLINDER_SURFACE", "CYLINDER_FIXED", "CYLINDER_DOMAIN", "CONTACT_UPPER", "PLATE_TOP", "PLATE_BOTTOM",
    "PLATE_SYMMETRY", "PLATE", "HERTZ_FACETS", "PIN_FACETS", "SHEET_FACETS", "RECTANGLE_FACETS", "RING_OUTER",
    "RING_INNER", "RING_AXIS", "RING_MID", "RING_FACETS", "SEAL_BOUNDARY", "SEAL_SYMMETRY", "SEAL_DOMAIN"
]

DOMAIN = 1
CONTACT = 1
SYMMETRY = 2
TOP = 3
FREE = 4  # traction-free sides of ``pin_plate``
# Facet tags of ``rectangle`` (its top is RECT_TOP: TOP is taken above).
BOTTOM = 11
RIGHT = 12
RECT_TOP = 13
LEFT = 14
# Facet tag of ``sphere_octant``'s second symmetry plane (y = 0; x = 0 is SYMMETRY).
SYMMETRY_Y = 4
# Facet tags of ``sheet_over_cylinder`` (CONTACT and SYMMETRY as above).
END = 4
# ... and with its deformable cylinder: outer surface, fixed inner surface (facets), the cylinder's cells.
CYLINDER_SURFACE = 5
CYLINDER_FIXED = 6
CYLINDER_DOMAIN = 2
# Extra tags of the hertz model-reduction meshes: the full disk's upper contact arc; the meshed plate's
# top (contact), bottom (fixed) and symmetry side, and the plate's cell tag.
CONTACT_UPPER = 5
PLATE_TOP, PLATE_BOTTOM, PLATE_SYMMETRY, PLATE = 6, 7, 8, 2
# Name -> tag maps, e.g. for ``check_tags``.
HERTZ_FACETS = {"contact": CONTACT, "symmetry": SYMMETRY, "top": TOP}
PIN_FACETS = {"contact": CONTACT, "symmetry": SYMMETRY, "top": TOP, "free": FREE}
SHEET_FACETS = {"contact": CONTACT, "symmetry": SYMMETRY, "end": END}
RECTANGLE_FACETS = {"bottom": BOTTOM, "right": RIGHT, "top": RECT_TOP, "left": LEFT}
# Facet tags of ``ring_quarter``.
RING_OUTER = 21
RING_INNER = 22
RING_AXIS = 23  # x = 0
RING_MID = 24  # the horizontal diameter y = R_out
RING_FACETS = {"outer": RING_OUTER, "inner": RING_INNER, "axis": RING_AXIS, "mid": RING_MID}
# Tags of ``seal_section``: the free boundary, the symmetry line x = 0, the cell tag.
SEAL_BOUNDARY = 31
SEAL_SYMMETRY = 32
SEAL_DOMAIN = 33
