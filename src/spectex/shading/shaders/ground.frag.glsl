{{! This file is a template (spectex/_template.py), filled in by spectex/shading/glsl.py with the
{{! switches' values, the inputs' declarations (spectex/shading/interface.py) and, per drawn layer, the
{{! "each layers" block in main(); these template comments are not part of the shader.
#define N_LAYERS {{n_layers}}
#define N_TILES {{n_tiles}}
#define ISO_LOD {{iso_lod}}
#define SKY_ONLY {{sky_only}}
#define STOCHASTIC {{any_stochastic}}
#define MIN_FILTER {{min_filter}}
// The spectral texture on the ground plane, with sky and haze: the
// renderer's main(), docs/sampling.md section 7, over the layer library
// (spectex_layers.glsl), which glsl.py includes before this text together
// with the prelude, the constants and these switches:
//   N_LAYERS, N_TILES  array sizes
//   ISO_LOD   1: each layer's lambda from the pixel's world lambda (section 3)
//   SKY_ONLY  1: the ground branch compiled out (rows that see only sky)
//   STOCHASTIC 1: some drawn layer is stochastic (section 6b): its textures and uniforms
//   MIN_FILTER the minification filter's code (SPX_FILTER_*)
// and the unrolled layer calls in place of the LAYERS marker below (only
// the drawn layers', each with its tile and blend code written in).

// The inputs (uniforms; in the renderer's shader, constants where they may be), written in place of
// this marker from the table of spectex/shading/interface.py:
{{inputs}}

out vec4 frag_colour;

// One layer over c (section 6). With ISO_LOD, its lambda is the pixel's
// world lambda plus the layer's offset (section 3); otherwise from its own
// derivatives (sections 3 and 5).
void shade_layer(int k, int blend, SPX_TEX_ARG(tile), inout vec3 c, vec2 p, vec2 jx, vec2 jy, float lam_w) {
#if ISO_LOD
    vec2 st = spectex_layer_coords(u_anchor[k], u_mat[k], p);
    vec4 x = spectex_sample_layer(SPX_TEX(tile), st, lam_w + u_lod_off[k]);
    c = spectex_blend(blend, c, x, u_opacity[k], u_mean[k], lam_w + u_lod_off[k] + u_fade_bias);
#else
    c = spectex_layer(blend, SPX_TEX(tile), c, u_anchor[k], u_mat[k], u_opacity[k], u_mean[k], p, jx, jy, u_tex_size,
                      u_max_aniso, u_fade_bias);
#endif
}

#if STOCHASTIC
// A stochastic layer over c (sections 6 and 6b); lambda as in shade_layer,
// from the un-offset coordinates.
void shade_layer_stochastic(int k, int blend, SPX_TEX_ARG(gauss), SPX_TEX_ARG(lut), inout vec3 c, vec2 p, vec2 jx,
                            vec2 jy, float lam_w) {
#if ISO_LOD
    vec4 m = u_mat[k];
    vec4 gm = u_grid[k];
    vec2 rel = spectex_layer_deriv(m, p);  // tile coordinates relative to the anchor
    vec2 g = u_ganchor[k] + vec2(gm.x * rel.x + gm.y * rel.y, gm.z * rel.x + gm.w * rel.y);
    float lam = lam_w + u_lod_off[k];
    vec4 x = spectex_sample_stochastic(SPX_TEX(gauss), SPX_TEX(lut), u_anchor[k] + rel, g, u_gbase[k].x, u_gbase[k].y,
                                       u_key[k], u_snap[k], u_tex_size, lam, MIN_FILTER, u_lut_q, u_lut_row[k],
                                       u_lut_rows, u_basis[k][0], u_basis[k][1], u_basis[k][2], u_origin[k], gm,
                                       u_cell_row[k]);
    c = spectex_blend(blend, c, x, u_opacity[k], u_mean[k], lam + u_fade_bias);
#else
    c = spectex_layer_stochastic(blend, SPX_TEX(gauss), SPX_TEX(lut), c, u_anchor[k], u_ganchor[k], u_gbase[k].x,
                                 u_gbase[k].y, u_mat[k], u_grid[k], u_key[k], u_snap[k], u_cell_row[k], u_lut_row[k],
                                 u_basis[k][0],
                                 u_basis[k][1], u_basis[k][2], u_origin[k], u_opacity[k], u_mean[k], p, jx, jy,
                                 u_tex_size, u_max_aniso, MIN_FILTER, u_lut_q, u_lut_rows, u_fade_bias);
#endif
}
#endif

void main() {
    // Pixel centres at half-integers, row 0 at the top; gl_FragCoord.y
    // counts from the bottom (render/gl.py's one GL convention here).
    vec2 pix = vec2(gl_FragCoord.x, u_size.y - gl_FragCoord.y);
    vec2 ndc = vec2(2.0 * pix.x / u_size.x - 1.0, 1.0 - 2.0 * pix.y / u_size.y);
    vec3 d = u_fwd + ndc.x * u_tan.x * u_right + ndc.y * u_tan.y * u_up;
    float dlen = length(d);
    vec3 col = u_horizon;
    // llvmpipe runs both sides of a branch for every pixel, so the sky rows
    // are drawn with SKY_ONLY: the same code without the ground branch.
    if (SKY_ONLY == 0 && d.z < 0.0 && u_height * dlen < -d.z * u_far) {
        float tt = u_height / -d.z;
        float q = tt / d.z;  // -height / d_z^2
        vec2 jx = q * (d.z * u_ddx.xy - d.xy * u_ddx.z);
        vec2 jy = q * (d.z * u_ddy.xy - d.xy * u_ddy.z);
        vec2 p = tt * d.xy;
        // (the floor on the squared length: its square would underflow in float32)
        float lam_w = 0.5 * log2(max(max(dot(jx, jx), dot(jy, jy)), SPX_LOD_FLOOR));
        vec3 c = vec3(0.0);  // black where every layer is off
{{#if open_layers}}
//@LAYERS@
{{/if}}
{{#each layers}}
{{#if stochastic}}
        shade_layer_stochastic({{k}}, {{blend}}, u_gauss[{{tile}}], u_lut, c, p, jx, jy, lam_w);
{{/if}}
{{#if not stochastic}}
        shade_layer({{k}}, {{blend}}, u_tile[{{tile}}], c, p, jx, jy, lam_w);
{{/if}}
{{/each}}
        col = spectex_haze(clamp(c, 0.0, 1.0), tt * dlen, u_horizon, u_haze);
    } else if (d.z > 0.0) {
        col = spectex_sky(d.z / dlen, u_horizon, u_zenith);
    }
    frag_colour = vec4(col, 1.0);
}
