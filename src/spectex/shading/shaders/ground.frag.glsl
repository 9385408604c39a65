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

uniform vec2 u_size;          // framebuffer width, height in pixels
uniform float u_height;       // camera altitude (z > 0)
uniform vec3 u_fwd;           // camera basis, world coordinates
uniform vec3 u_right;
uniform vec3 u_up;
uniform vec2 u_tan;           // tan_x, tan_y: half-extents of the image plane at distance 1
uniform vec3 u_ddx;           // d(ray)/d(pixel x) = right 2 tan_x / width (on the host: llvmpipe
uniform vec3 u_ddy;           // d(ray)/d(pixel y) = -up 2 tan_y / height  evaluates uniform math per pixel)
uniform vec3 u_horizon;
uniform vec3 u_zenith;
uniform float u_haze;         // haze distance (m)
uniform float u_far;          // beyond this distance: horizon colour, no texture
uniform float u_fade_bias;    // log2 of the supersampling factor (0 unless supersampled): the fine
                              // blend fades by the pixel's footprint, not the sample's

uniform sampler2D u_tile[N_TILES];
uniform vec2 u_tex_size;      // level-0 width, height in texels
uniform float u_max_aniso;    // 1: isotropic

uniform vec2 u_anchor[N_LAYERS];   // per layer: tile coords of the camera's ground point, mod 2
uniform vec4 u_mat[N_LAYERS];      // per layer: (m00, m01, m10, m11), world -> tile coords
uniform vec3 u_mean[N_LAYERS];     // per layer: its tile's mean colour (1 x 1 level)
uniform float u_opacity[N_LAYERS]; // per layer: alpha = opacity * tile alpha
uniform float u_lod_off[N_LAYERS]; // per layer: log2(tile width / layer size), texels per metre

#if STOCHASTIC
uniform sampler2D u_gauss[N_TILES]; // per tile: its Gaussianised levels (half-float values)
uniform sampler2D u_lut;           // the inverse tables, SPX_LUT_SIZE x 4 u_lut_rows (one channel, NEAREST)
uniform float u_lut_rows;          // rows of u_lut per channel
uniform float u_lut_q;             // the last mip level (rows per tile - 1 with mip-maps, else 0)
uniform vec4 u_grid[N_LAYERS];     // per layer: tile coords -> skewed grid coords (m00, m01, m10, m11)
uniform vec2 u_ganchor[N_LAYERS];  // per layer: the anchor's grid position minus its vertex
uniform uvec2 u_gbase[N_LAYERS];   // per layer: that grid vertex, mod 2^32
uniform uint u_key[N_LAYERS];      // per layer: the hash key of its seed
uniform vec2 u_snap[N_LAYERS];     // per layer: its snap counts (whole numbers; tables.snap_counts)
uniform float u_lut_row[N_LAYERS]; // per layer: first table row of its tile
uniform mat3 u_basis[N_LAYERS];    // per layer: its tile's decorrelation, RGB = origin + basis v
uniform vec3 u_origin[N_LAYERS];
#endif

out vec4 frag_colour;

// One layer over c (section 6). With ISO_LOD, its lambda is the pixel's
// world lambda plus the layer's offset (section 3); otherwise from its own
// derivatives (sections 3 and 5).
void shade_layer(int k, int blend, SPX_TEX_ARG(tile), inout vec3 c, vec2 p, vec2 jx, vec2 jy, float lam_w) {
    vec4 m = u_mat[k];
    vec2 st = spectex_layer_coords(u_anchor[k], m, p);
#if ISO_LOD
    float lam = lam_w + u_lod_off[k];
    vec4 x = spectex_sample_layer(SPX_TEX(tile), st, lam);
#else
    vec2 dx = spectex_layer_deriv(m, jx);
    vec2 dy = spectex_layer_deriv(m, jy);
    // the fine layer isotropic (spectex_blend: it fades out before anisotropy would matter)
    vec4 x = spectex_sample_grad(SPX_TEX(tile), st, dx, dy, u_tex_size, (blend == SPX_BLEND_FINE) ? 1.0 : u_max_aniso);
    float lam = (blend == SPX_BLEND_FINE || blend == SPX_BLEND_COVER) ? spectex_fade_lod(dx, dy, u_tex_size) : 0.0;
#endif
    c = spectex_blend(blend, c, x, u_opacity[k], u_mean[k], lam + u_fade_bias);
}

#if STOCHASTIC
// A stochastic layer over c (sections 6 and 6b); lambda as in shade_layer,
// from the un-offset coordinates.
void shade_layer_stochastic(int k, int blend, SPX_TEX_ARG(gauss), SPX_TEX_ARG(lut), inout vec3 c, vec2 p, vec2 jx,
                            vec2 jy, float lam_w) {
    vec4 m = u_mat[k];
    vec4 gm = u_grid[k];
    vec2 rel = spectex_layer_deriv(m, p);  // tile coordinates relative to the anchor
    vec2 st = u_anchor[k] + rel;
    vec2 g = u_ganchor[k] + vec2(gm.x * rel.x + gm.y * rel.y, gm.z * rel.x + gm.w * rel.y);
#if ISO_LOD
    float lam = lam_w + u_lod_off[k];
    vec4 x = spectex_sample_stochastic(SPX_TEX(gauss), SPX_TEX(lut), st, g, u_gbase[k].x, u_gbase[k].y, u_key[k],
                                       u_snap[k], u_tex_size, lam, MIN_FILTER, u_lut_q, u_lut_row[k], u_lut_rows,
                                       u_basis[k][0], u_basis[k][1], u_basis[k][2], u_origin[k]);
#else
    vec4 x = spectex_sample_stochastic_grad(SPX_TEX(gauss), SPX_TEX(lut), st, g, u_gbase[k].x, u_gbase[k].y,
                                            u_key[k], u_snap[k], spectex_layer_deriv(m, jx), spectex_layer_deriv(m, jy),
                                            u_tex_size, (blend == SPX_BLEND_FINE) ? 1.0 : u_max_aniso, gm, MIN_FILTER, u_lut_q, u_lut_row[k],
                                            u_lut_rows, u_basis[k][0], u_basis[k][1], u_basis[k][2], u_origin[k]);
    float lam = (blend == SPX_BLEND_FINE || blend == SPX_BLEND_COVER)
        ? spectex_fade_lod(spectex_layer_deriv(m, jx), spectex_layer_deriv(m, jy), u_tex_size) : 0.0;
#endif
    c = spectex_blend(blend, c, x, u_opacity[k], u_mean[k], lam + u_fade_bias);
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
//@LAYERS@
        col = spectex_haze(clamp(c, 0.0, 1.0), tt * dlen, u_horizon, u_haze);
    } else if (d.z > 0.0) {
        col = spectex_sky(d.z / dlen, u_horizon, u_zenith);
    }
    frag_colour = vec4(col, 1.0);
}
