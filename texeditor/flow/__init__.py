"""Flow fields for directional textures (companion document 004): a photo's orientation field
(structure tensor) or one drawn as strokes, and line integral convolution of seeded noise along
it — wood, hair, grass, brushed metal whose grain follows a direction the user chooses.

``orientation_field(photo)`` and ``strokes_field(strokes, shape)`` give the field (θ, coherence);
``line_integral_convolution(θ, L, seed=S)`` the picture; ``flow_texture(...)`` photo or strokes → picture in one call;
``FlowTexture`` the step.
"""

from .field import orientation_field, strokes_field
from .lic import contrast, line_integral_convolution
from .texture import flow_texture
from .actions import FlowTexture

__all__ = ["orientation_field", "strokes_field", "line_integral_convolution", "contrast",
           "flow_texture", "FlowTexture"]
