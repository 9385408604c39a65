{{! The layer library as the shaders include it (spectex/shading/glsl.py's layer_library, a template of
{{! spectex/_template.py): the constants of spectex/shading/constants.py, the anisotropic path's
{{! switch, then spectex_layers.glsl.
{{defines}}
#define SPX_ANISO {{aniso}}
{{library}}
