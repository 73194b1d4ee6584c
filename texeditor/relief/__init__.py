"""Relief (companion document 003): the texture as a height map, its bump normals and Lambert
shading, previews on a plane and a sphere, and height and normal map exports. No Actions: these
are views and exports of a document, never changes to it.
"""

from .maps import (NORMAL_CONVENTIONS, encode_normals, height_map16, write_height_map,
                   write_normal_map)
from .previews import plane_preview, sphere_preview
from .shading import (heights, lambert, light_direction, normal_map, palette_grey, shade, slopes,
                      unit_normals)

__all__ = ["NORMAL_CONVENTIONS", "encode_normals", "height_map16", "write_height_map",
           "write_normal_map", "plane_preview", "sphere_preview", "heights", "lambert",
           "light_direction", "normal_map", "palette_grey", "shade", "slopes", "unit_normals"]
