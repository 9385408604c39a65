{{! The opening lines of a GLSL shader after version.glsl (spectex/shading/glsl.py's prelude, a template of
{{! spectex/_template.py): GLSL ES's int and sampler precision, then the texture macros
{{! the layer library is written with (texture_macros.glsl).
{{#if not desktop}}
precision highp int;
precision highp sampler2D;
{{/if}}
{{macros}}
