{{! The opening lines of a GLSL shader (spectex/shading/glsl.py's prelude, a template of
{{! spectex/_template.py): the target's #version (and GLSL ES's precision), then the texture macros
{{! the layer library is written with (texture_macros.glsl).
{{#if desktop}}
#version 330 core
{{/if}}
{{#if not desktop}}
#version 300 es
precision highp float;
precision highp int;
precision highp sampler2D;
{{/if}}
{{macros}}
