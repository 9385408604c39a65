// spectex spectral texture for Unity Shader Graph (Custom Function, file mode, name
// "SpectexGround") and Unreal (Custom node with this file as an include), written by
// `spectex export` (docs/export.md).
// {{n_layers}} layers over {{n_tiles}} tile(s) of {{width}} x {{height}} texels ({{tile_files}}): {{sizes}}.
// The layer library below is spectex's own (spectex/shading/shaders/spectex_layers.glsl), unchanged.
#ifndef SPECTEX_GROUND_INCLUDED
#define SPECTEX_GROUND_INCLUDED

{{prelude}}{{library}}
// ---- the texture's layers
static const float4 SPECTEX_MAT[{{n_layers}}] = {{MAT}};
static const float3 SPECTEX_MEAN[{{n_layers}}] = {{MEAN}};
static const float SPECTEX_OPACITY[{{n_layers}}] = {{OPACITY}};
// each layer's tile coordinates of the ground point (0, 0), computed in float64, mod 2
static const float2 SPECTEX_ORIGIN_ANCHOR[{{n_layers}}] = {{ORIGIN_ANCHOR}};
static const float2 SPECTEX_TEX_SIZE = {{TEX_SIZE}};
{{#if stochastic}}
// ---- stochastic layers: per layer its tile -> triangle-grid map, hash key, snap counts, first table row,
// decorrelation (RGB = origin + b0 v.x + b1 v.y + b2 v.z) and the grid position of ground (0, 0)
static const float4 SPECTEX_GRID[{{n_layers}}] = {{GRID}};
static const uint SPECTEX_KEY[{{n_layers}}] = {{KEY}};
static const float2 SPECTEX_SNAP[{{n_layers}}] = {{SNAP}};
static const float SPECTEX_LUT_ROW[{{n_layers}}] = {{LUT_ROW}};
static const float SPECTEX_CELL_ROW[{{n_layers}}] = {{CELL_ROW}};
static const float3 SPECTEX_B0[{{n_layers}}] = {{BASIS0}};
static const float3 SPECTEX_B1[{{n_layers}}] = {{BASIS1}};
static const float3 SPECTEX_B2[{{n_layers}}] = {{BASIS2}};
static const float3 SPECTEX_ORIGIN_RGB[{{n_layers}}] = {{ORIGIN}};
static const float2 SPECTEX_ORIGIN_GANCHOR[{{n_layers}}] = {{ORIGIN_GANCHOR}};
static const uint2 SPECTEX_ORIGIN_GBASE[{{n_layers}}] = {{ORIGIN_GBASE}};
static const float SPECTEX_LUT_ROWS = {{LUT_ROWS}};
static const float SPECTEX_LUT_Q = {{LUT_Q}};
{{/if}}
#ifdef SPECTEX_ANCHORED
// Set by the host every frame, in float64 there: per layer, its tile coordinates (s, t) at the
// anchor point mod 2 (xy) and, for a stochastic layer, the anchor's triangle-grid fraction (zw);
// the grid vertex mod 2^32 as whole 16-bit halves (x_hi, x_lo, y_hi, y_lo). Ground is then
// relative to the anchor point (README.md).
float4 SpectexAnchor[{{n_layers}}];
float4 SpectexGridBase[{{n_layers}}];
#define SPECTEX_ST_ANCHOR(k) SpectexAnchor[k].xy
#define SPECTEX_G_ANCHOR(k) SpectexAnchor[k].zw
#define SPECTEX_G_BASE(k) (uint2(SpectexGridBase[k].xz) * 65536u + uint2(SpectexGridBase[k].yw))
#else
#define SPECTEX_ST_ANCHOR(k) SPECTEX_ORIGIN_ANCHOR[k]
#define SPECTEX_G_ANCHOR(k) SPECTEX_ORIGIN_GANCHOR[k]
#define SPECTEX_G_BASE(k) SPECTEX_ORIGIN_GBASE[k]
#endif
#ifndef SPECTEX_MAX_ANISOTROPY
#define SPECTEX_MAX_ANISOTROPY {{max_anisotropy}}  // spectex's own anisotropic filter; 1 = off
#endif

// Ground: the spectex ground point in metres (x east, y north). In a pixel shader only
// (the footprint comes from ddx/ddy). Color: spectex's colour; Linear: decoded from sRGB.
void {{entry_point}}(float2 Ground, {{texture_params}}, out float3 Color, out float3 Linear) {
    vec2 p = Ground;
    vec2 jx = ddx(p);
    vec2 jy = ddy(p);
    vec3 c = float3(0.0, 0.0, 0.0);
    // each layer over c: the library's layer step (spectex_layers.glsl), as in spectex's own renderer
{{#each layers}}
{{#if stochastic}}
    c = spectex_layer_stochastic({{blend}}, SPX_TEX(Gauss{{tile}}), SPX_TEX(Lut), c, SPECTEX_ST_ANCHOR({{k}}),
        SPECTEX_G_ANCHOR({{k}}), SPECTEX_G_BASE({{k}}).x, SPECTEX_G_BASE({{k}}).y, SPECTEX_MAT[{{k}}], SPECTEX_GRID[{{k}}],
        SPECTEX_KEY[{{k}}], SPECTEX_SNAP[{{k}}], SPECTEX_CELL_ROW[{{k}}], SPECTEX_LUT_ROW[{{k}}], SPECTEX_B0[{{k}}], SPECTEX_B1[{{k}}], SPECTEX_B2[{{k}}], SPECTEX_ORIGIN_RGB[{{k}}],
        SPECTEX_OPACITY[{{k}}], SPECTEX_MEAN[{{k}}], p, jx, jy, SPECTEX_TEX_SIZE, SPECTEX_MAX_ANISOTROPY,
        SPX_FILTER_LINEAR_MIPMAP_LINEAR, SPECTEX_LUT_Q, SPECTEX_LUT_ROWS, 0.0);
{{/if}}
{{#if not stochastic}}
    c = spectex_layer({{blend}}, SPX_TEX(Tile{{tile}}), c, SPECTEX_ST_ANCHOR({{k}}), SPECTEX_MAT[{{k}}], SPECTEX_OPACITY[{{k}}],
        SPECTEX_MEAN[{{k}}], p, jx, jy, SPECTEX_TEX_SIZE, SPECTEX_MAX_ANISOTROPY, 0.0);
{{/if}}
{{/each}}
    Color = saturate(c);
    float3 lo = Color / 12.92;
    float3 hi = pow((Color + 0.055) / 1.055, float3(2.4, 2.4, 2.4));
    Linear = lerp(hi, lo, step(Color, float3(0.04045, 0.04045, 0.04045)));  // lo where Color <= 0.04045
}

#undef vec2
#undef vec3
#undef vec4
#undef SPX_TEX_ARG
#undef SPX_TEX
#undef SPX_LOD
#undef SPX_UINT
#undef SPECTEX_ST_ANCHOR
#undef SPECTEX_G_ANCHOR
#undef SPECTEX_G_BASE
#endif  // SPECTEX_GROUND_INCLUDED
