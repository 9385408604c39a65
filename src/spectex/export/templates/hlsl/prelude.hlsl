// HLSL for the GLSL-subset layer library: vector types, textures as Texture2D +
// SamplerState (Unreal names a texture input's sampler <name>Sampler; use the same in
// Unity), SampleLevel for textureLod. Undefined again at the end of this file.
#define vec2 float2
#define vec3 float3
#define vec4 float4
#define SPX_TEX_ARG(name) Texture2D name, SamplerState name##Sampler
#define SPX_TEX(name) name, name##Sampler
#define SPX_UINT uint
// Unity addresses textures with v = 0 at the bottom row of the image, Unreal at the
// top; spectex's t = 0 is the image's first (top) row: flip t under Unity (v = 1 - t,
// for the clamped look-up table too; load the raw tables bottom row first there).
#ifndef SPECTEX_FLIP_V
#ifdef UNITY_VERSION
#define SPECTEX_FLIP_V 1
#else
#define SPECTEX_FLIP_V 0
#endif
#endif
#if SPECTEX_FLIP_V
#define SPX_LOD(name, uv, lod) name.SampleLevel(name##Sampler, float2(1.0, -1.0) * (uv) + float2(0.0, 1.0), lod)
#else
#define SPX_LOD(name, uv, lod) name.SampleLevel(name##Sampler, uv, lod)
#endif
