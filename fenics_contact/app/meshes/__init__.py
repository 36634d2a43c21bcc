"""Meshes for the contact benchmarks, with named regions; one module per geometry.

Every builder returns ``(mesh, cells, facets)``, the tags as :class:`~fenics_contact.domain.NamedTags` (``cells`` is
None for the single-body built-in meshes): boundaries and bodies are referred to by their physical names
(``facets["contact"]``, or the name itself wherever the library takes a tag). gmsh meshes (``hertz_quarter_disk``,
``pin_plate``, the seal sections, ``two_half_disks``, ``sheet_over_cylinder``, ``sphere_octant``, ``cap_on_block``,
``concentric_rings``, ``cord_section``) are meshed from the gmsh geometry sources of ``fenics_contact/app/geo``
(``hertz.geo``, ``pin.geo``, ``seal.geo``, ``two_disks.geo``, ``sheet.geo``, ``sphere.geo``, ``mindlin3d.geo``,
``rings.geo``, ``oring.geo``: parametrised with ``DefineConstant``, openable in the gmsh GUI; the builder sets the
parameters) on rank 0 and distributed with ``dolfinx.io.gmshio.model_to_mesh``; ``rectangle`` and ``stacked_blocks``
use dolfinx's built-in meshes, ``ring_quarter`` maps a rectangle to polar coordinates. All functions are collective
on ``comm``. The seal geometry is documented in :mod:`fenics_contact.app.meshes.seal`.
"""
from .hertz import hertz_quarter_disk
from .mindlin3d import cap_on_block
from .oring import cord_section, gland_section
from .pin import pin_plate
from .rectangle import check_tags, rectangle
from .ring import ring_quarter
from .rings import concentric_rings
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
from .twobody import stacked_blocks, two_half_disks

__all__ = [
    "hertz_quarter_disk", "pin_plate", "check_tags", "rectangle", "ring_quarter", "concentric_rings",
    "seal_geometry", "seal_s_geometry", "seal_s_section", "seal_section", "seal_wave_geometry", "seal_wave_section",
    "sheet_over_cylinder", "sphere_octant", "stacked_blocks", "two_half_disks", "cap_on_block", "cord_section",
    "gland_section",
]
