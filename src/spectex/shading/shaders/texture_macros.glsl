#define SPX_TEX_ARG(name) sampler2D name
#define SPX_TEX(name) name
#define SPX_LOD(name, uv, lod) textureLod(name, uv, lod)
#define SPX_UINT uint
