"""The OpenGL-exact reference sampler: ``spectex.shading.sampler`` under its public name.

The sampler is the bottom of the shading core (``spectex.shading``); this
module keeps the name users import it by.
"""

from .shading.sampler import (  # noqa: F401
                              FILTERS,
                              MAX_TEXELS,
                              WRAP_MODES,
                              MipTexture,
                              default_mip_chain,
                              filter_code,
                              gl_level_shapes,
                              level_of_detail,
                              quantize,
                              sample,
                              wrap_code,
)

__all__ = ["WRAP_MODES", "FILTERS", "MipTexture", "sample", "level_of_detail", "gl_level_shapes", "quantize",
           "filter_code", "wrap_code"]
