{{! The full-screen triangle's vertex shader (spectex/shading/glsl.py's vertex_source, a template of
{{! spectex/_template.py): the target's #version (and GLSL ES's float precision), then the shader.
{{#if desktop}}
#version 330 core
{{/if}}
{{#if not desktop}}
#version 300 es
precision highp float;
{{/if}}
// One triangle that covers the viewport; no vertex buffer needed.
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
