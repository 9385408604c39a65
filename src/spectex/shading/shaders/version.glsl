{{! The first lines of every spectex shader (spectex/shading/glsl.py puts it before prelude.glsl and
{{! fullscreen.vert.glsl): the target's #version, and GLSL ES's float precision.
{{#if desktop}}
#version 330 core
{{/if}}
{{#if not desktop}}
#version 300 es
precision highp float;
{{/if}}
