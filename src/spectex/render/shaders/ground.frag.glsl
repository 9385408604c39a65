#version 330 core
// The spectral texture on the ground plane, with sky and haze.
// This shader implements docs/sampling.md, section by section; the CPU
// reference (spectex/sampling.py, spectex/render/_kernels.py) implements the
// same text. gl.py fills in N_LAYERS, N_TILES, ANISO, ISO_LOD, SKY_ONLY and
// the unrolled layer calls (only the enabled layers', the first one with
// blend -1: it sets the colour).

#define N_LAYERS @N_LAYERS@
#define N_TILES @N_TILES@
#define ANISO @ANISO@             // 1: compile the anisotropic path
#define ISO_LOD @ISO_LOD@         // 1: each layer's lambda from the pixel's world lambda (square tiles, no anisotropy)
#define SKY_ONLY @SKY_ONLY@       // 1: the ground branch compiled out (gl.py draws rows that see only sky with it)

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

uniform sampler2D u_tile[N_TILES];
uniform vec2 u_tex_size;      // level-0 width, height in texels
uniform float u_max_aniso;    // 1: isotropic
uniform int u_mipmapped;      // 1 when the minification filter uses mip-maps

uniform vec2 u_anchor[N_LAYERS];  // per layer: tile coords of the camera's ground point, mod 2
uniform vec4 u_mat[N_LAYERS];     // per layer: (m00, m01, m10, m11), world -> tile coords
uniform vec3 u_mean[N_LAYERS];    // per layer: its tile's mean colour (1 x 1 level)
uniform float u_opacity[N_LAYERS]; // per layer: alpha = opacity * tile alpha
uniform float u_lod_off[N_LAYERS]; // per layer: log2(tile width / layer size), texels per metre

out vec4 frag_colour;

// Section "Level of detail and anisotropy": lambda from the derivatives of
// (s, t), then textureLod, whose filtering and level selection are OpenGL's.
vec4 sample_grad(sampler2D tex, vec2 st, vec2 dx, vec2 dy) {
    vec2 ux = dx * u_tex_size;
    vec2 uy = dy * u_tex_size;
    float px = length(ux);
    float py = length(uy);
    float pmax = max(px, py);
#if ANISO
    if (u_max_aniso > 1.0 && u_mipmapped == 1) {
        float pmin = min(px, py);
        float n_max = floor(u_max_aniso);
        float n = (pmin * n_max <= pmax) ? n_max : min(ceil(pmax / pmin), n_max);
        if (n > 1.0) {
            float lam = log2(max(pmax / n, 1e-30));
            vec2 d = (px >= py) ? dx : dy;
            vec4 acc = vec4(0.0);
            for (float i = 1.0; i <= n; i += 1.0) {
                acc += textureLod(tex, st + (i / (n + 1.0) - 0.5) * d, lam);
            }
            return acc / n;
        }
    }
#endif
    return textureLod(tex, st, log2(max(pmax, 1e-30)));
}

// Section "Layer compositing". blend: -1 the first drawn layer (sets the
// colour), 0 alpha, 1 detail, 2 variance: a constant at each call site,
// written in by gl.py with the layer toggles, so that no branch is left.
// With ISO_LOD, section "Level of detail": a layer's map is a rotation and
// a scale, so its lambda is the pixel's world lambda (log2 of the longer
// footprint edge in metres, computed once in main) plus log2(w / size_k).
void shade_layer(int k, int blend, sampler2D tex, inout vec3 c, vec2 p, vec2 jx, vec2 jy, float lam_w) {
    vec4 m = u_mat[k];
    vec2 st = u_anchor[k] + vec2(m.x * p.x + m.y * p.y, m.z * p.x + m.w * p.y);
#if ISO_LOD
    vec4 x = textureLod(tex, st, lam_w + u_lod_off[k]);
#else
    vec2 dx = vec2(m.x * jx.x + m.y * jx.y, m.z * jx.x + m.w * jx.y);
    vec2 dy = vec2(m.x * jy.x + m.y * jy.y, m.z * jy.x + m.w * jy.y);
    vec4 x = sample_grad(tex, st, dx, dy);
#endif
    float a = x.a * u_opacity[k];
    if (blend == -1) {
        c = x.rgb;
    } else if (blend == 0) {
        c = a * x.rgb + (1.0 - a) * c;
    } else if (blend == 1) {
        c = 2.0 * x.rgb * c;
    } else {
        vec3 mu = u_mean[k];
        c = mu + (a * (x.rgb - mu) + (1.0 - a) * (c - mu)) / sqrt(a * a + (1.0 - a) * (1.0 - a));
    }
}

void main() {
    // Section "Camera": pixel centres at half-integers, row 0 at the top.
    // gl.py's only convention here: gl_FragCoord.y counts from the bottom.
    vec2 pix = vec2(gl_FragCoord.x, u_size.y - gl_FragCoord.y);
    vec2 ndc = vec2(2.0 * pix.x / u_size.x - 1.0, 1.0 - 2.0 * pix.y / u_size.y);
    vec3 d = u_fwd + ndc.x * u_tan.x * u_right + ndc.y * u_tan.y * u_up;
    float dlen = length(d);
    vec3 col = u_horizon;
    // llvmpipe runs both sides of a branch for every pixel, so the sky rows
    // are drawn with SKY_ONLY: the same code without the ground branch.
    if (SKY_ONLY == 0 && d.z < 0.0 && u_height * dlen < -d.z * u_far) {
        float tt = u_height / -d.z;
        float dist = tt * dlen;
        float q = tt / d.z;  // -height / d_z^2
        vec2 jx = q * (d.z * u_ddx.xy - d.xy * u_ddx.z);
        vec2 jy = q * (d.z * u_ddy.xy - d.xy * u_ddy.z);
        vec2 p = tt * d.xy;
        float lam_w = 0.5 * log2(max(max(dot(jx, jx), dot(jy, jy)), 1e-30));
        vec3 c = vec3(0.0);  // black where every layer is off
//@LAYERS@
        c = clamp(c, 0.0, 1.0);
        col = u_horizon + exp(-dist / u_haze) * (c - u_horizon);
    } else if (d.z > 0.0) {
        col = u_horizon + (1.0 - exp(-4.0 * d.z / dlen)) * (u_zenith - u_horizon);
    }
    frag_colour = vec4(col, 1.0);
}
