// spectex layer library: the per-layer part of docs/sampling.md (sections 3-7),
// self-contained: it reads no uniform and no global; everything comes by
// argument, so that the renderer (ground.frag.glsl) and every export
// (WebGL2, GLSL 3.30, Godot, HLSL) include this same text after a prelude
// (spectex/shading/glsl.py) that defines
//   SPX_TEX_ARG(name)       a texture parameter      (GLSL: sampler2D name)
//   SPX_TEX(name)           passing it on            (GLSL: name)
//   SPX_LOD(name, uv, lod)  a sample at a given lod  (GLSL: textureLod(name, uv, lod))
//   SPX_ANISO               1 to compile the anisotropic path (section 5)
// and the constants of spectex/shading/constants.py (SPX_BLEND_*, ...).
// Only vec2/vec3/vec4, float, int and functions common to GLSL and HLSL
// (floor, ceil, log2, exp, sqrt, length, dot, min, max, clamp) are used.

// Section 6: a ground point p (metres from the anchor) in a layer's tile
// coordinates; m = (m00, m01, m10, m11) is the layer's map, anchor its
// coordinates of the anchor point (float64 on the host, mod 2).
vec2 spectex_layer_coords(vec2 anchor, vec4 m, vec2 p) {
    return anchor + vec2(m.x * p.x + m.y * p.y, m.z * p.x + m.w * p.y);
}

// A world-space footprint vector pushed through a layer's map.
vec2 spectex_layer_deriv(vec4 m, vec2 j) {
    return vec2(m.x * j.x + m.y * j.y, m.z * j.x + m.w * j.y);
}

// Sections 3 and 5: lambda from the derivatives of (s, t), in texels of
// level 0 (tex_size = level-0 width, height), then samples at that lambda;
// with SPX_ANISO, EXT_texture_filter_anisotropic's recipe (max_aniso > 1).
vec4 spectex_sample_grad(SPX_TEX_ARG(tile), vec2 st, vec2 dx, vec2 dy, vec2 tex_size, float max_aniso) {
    vec2 ux = dx * tex_size;
    vec2 uy = dy * tex_size;
    float px = length(ux);
    float py = length(uy);
    float pmax = max(px, py);
#if SPX_ANISO
    if (max_aniso > 1.0) {
        float pmin = min(px, py);
        float n_max = floor(max_aniso);
        float n = (pmin * n_max <= pmax) ? n_max : min(ceil(pmax / pmin), n_max);
        if (n > 1.0) {
            float lam = log2(max(pmax / n, SPX_LOD_FLOOR));
            vec2 d = (px >= py) ? dx : dy;
            vec4 acc = vec4(0.0, 0.0, 0.0, 0.0);
            for (float i = 1.0; i <= n; i += 1.0) {
                acc += SPX_LOD(tile, st + (i / (n + 1.0) - 0.5) * d, lam);
            }
            return acc / n;
        }
    }
#endif
    return SPX_LOD(tile, st, log2(max(pmax, SPX_LOD_FLOOR)));
}

// Sections 3-4 for a periodic layer (SPX_TILING_PERIODIC) at a known lambda:
// the tile repeats (the texture's wrap mode is REPEAT).
vec4 spectex_sample_layer(SPX_TEX_ARG(tile), vec2 st, float lod) {
    return SPX_LOD(tile, st, lod);
}

// Section 6: the colour after a layer's sample x (RGBA) goes over c.
// blend: SPX_BLEND_FIRST (the first drawn layer: sets the colour),
// SPX_BLEND_ALPHA, SPX_BLEND_DETAIL or SPX_BLEND_VARIANCE (mean: the
// layer's tile mean colour). Pass a constant and the branches fold away.
vec3 spectex_blend(int blend, vec3 c, vec4 x, float opacity, vec3 mean) {
    float a = x.a * opacity;
    if (blend == SPX_BLEND_FIRST) {
        return x.rgb;
    } else if (blend == SPX_BLEND_ALPHA) {
        return a * x.rgb + (1.0 - a) * c;
    } else if (blend == SPX_BLEND_DETAIL) {
        return 2.0 * x.rgb * c;
    }
    return mean + (a * (x.rgb - mean) + (1.0 - a) * (c - mean)) / sqrt(a * a + (1.0 - a) * (1.0 - a));
}

// Section 7: distance haze over the ground colour c at distance dist.
vec3 spectex_haze(vec3 c, float dist, vec3 horizon, float haze_distance) {
    return horizon + exp(-dist / haze_distance) * (c - horizon);
}

// Section 7: the sky at elevation d_z / |d| (> 0).
vec3 spectex_sky(float elevation, vec3 horizon, vec3 zenith) {
    return horizon + (1.0 - exp(-SPX_SKY_FALLOFF * elevation)) * (zenith - horizon);
}
