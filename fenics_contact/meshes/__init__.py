"""Meshes for the contact benchmarks, with named physical tags; one module per geometry.

gmsh meshes (``hertz_quarter_disk``, ``pin_plate``, the seal sections, ``two_half_disks``,
``sheet_over_cylinder``, ``sphere_octant``) are built on rank 0 and distributed with
``dolfinx.io.gmshio.model_to_mesh``;
``rectangle`` and ``stacked_blocks`` use dolfinx's built-in meshes, ``ring_quarter`` maps a rectangle
to polar coordinates. All functions are collective on ``comm``. The seal geometry is documented in
:mod:`fenics_contact.meshes.seal`.
"""
from .hertz import hertz_quarter_disk
from .pin import pin_plate
from .rectangle import check_tags, rectangle
from .ring import ring_quarter
from .seal import (
    seal_geometry,
    seal_s_geometry,
    seal_s_section,
    seal_section,
    seal_wave_geometry,
    seal_wave_section,
)
from .sheet import sheet_over_cylinder
from .sphere import sphere_octant
from .tags import (
    BOTTOM,
    CONTACT,
    CONTACT_UPPER,
    CYLINDER_DOMAIN,
    CYLINDER_FIXED,
    CYLINDER_SURFACE,
    DOMAIN,
    END,
    FREE,
    HERTZ_FACETS,
    LEFT,
    PIN_FACETS,
    PLATE,
    PLATE_BOTTOM,
    PLATE_SYMMETRY,
    PLATE_TOP,
    RECT_TOP,
    RECTANGLE_FACETS,
    RIGHT,
    RING_AXIS,
    RING_FACETS,
    RING_INNER,
    RING_MID,
    RING_OUTER,
    SEAL_BOUNDARY,
    SEAL_DOMAIN,
    SEAL_SYMMETRY,
    SHEET_FACETS,
    SYMMETRY,
    SYMMETRY_Y,
    TOP,
)
from .twobody import (
    BLOCK_FRONT,
    BLOCK_LEFT,
    DISK_SYMMETRY,
    DISKS_FACETS,
    LOWER,
    LOWER_ARC_BOTTOM,
    LOWER_ARC_TOP,
    LOWER_BOTTOM,
    LOWER_TOP,
    STACKED_FACETS,
    UPPER,
    UPPER_ARC_BOTTOM,
    UPPER_ARC_TOP,
    UPPER_BOTTOM,
    UPPER_TOP,
    stacked_blocks,
    two_half_disks,
)

__all__ = [
    "hertz_quarter_disk", "pin_plate", "check_tags", "rectangle", "ring_quarter", "seal_geometry", "seal_s_geometry",
    "seal_s_section", "seal_section", "seal_wave_geometry", "seal_wave_section", "sheet_over_cylinder",
    "sphere_octant", "BOTTOM", "CONTACT", "CONTACT_UPPER", "CYLINDER_DOMAIN", "CYLINDER_FIXED", "CYLINDER_SURFACE",
    "DOMAIN", "END", "FREE", "HERTZ_FACETS", "LEFT", "PIN_FACETS", "PLATE", "PLATE_BOTTOM", "PLATE_SYMMETRY",
    "PLATE_TOP", "RECT_TOP", "RECTANGLE_FACETS", "RIGHT", "RING_AXIS", "RING_FACETS", "RING_INNER", "RING_MID",
    "RING_OUTER", "SEAL_BOUNDARY", "SEAL_DOMAIN", "SEAL_SYMMETRY", "SHEET_FACETS", "SYMMETRY", "SYMMETRY_Y", "TOP",
    "BLOCK_FRONT", "BLOCK_LEFT", "DISK_SYMMETRY", "DISKS_FACETS", "LOWER", "LOWER_ARC_BOTTOM", "LOWER_ARC_TOP",
    "LOWER_BOTTOM", "LOWER_TOP", "STACKED_FACETS", "UPPER", "UPPER_ARC_BOTTOM", "UPPER_ARC_TOP", "UPPER_BOTTOM",
    "UPPER_TOP", "stacked_blocks", "two_half_disks"
]
