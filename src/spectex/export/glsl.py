"""The ``glsl`` export: the renderer's shaders as GLSL ES 3.00 (WebGL2, three.js) and GLSL 3.30.

``glsl/`` holds:

* ``spectex_layers.es300.glsl`` and ``spectex_layers.330.glsl``: the layer
  library alone (the prelude, the generated constants and
  ``shading/shaders/spectex_layers.glsl``), to put before an engine's own
  ``main()``;
* ``ground.es300.vert``/``.frag`` and ``ground.330.vert``/``.frag``: the
  renderer's own ground program (a full-screen triangle; every pixel casts
  its ray to the ground plane, samples the layers, adds sky and haze),
  every layer drawn, the anisotropic path compiled in (``u_max_aniso = 1``
  turns it off);
* ``spectex_texture.json``: the layer table (matrices, offsets, opacities,
  level-of-detail offsets, mean colours) and the atmosphere;
* ``spectex_uniforms.js``: the shader's uniforms from that table and a
  camera, as an ES module (the web viewer's own code);
* ``tile.png`` and ``mips/tile.level<d>.png``: the tile and every mip level
  spectex samples (:func:`spectex.shading.resources.mip_levels`), lossless, for
  engines that accept given mip levels (three.js ``texture.mipmaps``);
* for a texture with stochastic layers, their tables (:mod:`spectex.export._stochastic`):
  ``gauss.rgba16f`` (per tile, its Gaussianised levels) and ``spectex_lut.r16f``
  (the look-up table texture), raw little-endian half floats, lossless;
* ``README.md``: how to use them (three.js and plain OpenGL).
"""

from __future__ import annotations

import json
from pathlib import Path

from ..shading.resources import mip_levels
from ._shader import GLSL_TARGETS, ground_fragment, has_stochastic, layer_library, prelude, vertex_source

__all__ = ["write_glsl"]


def _readme(texture, tiles, levels) -> str:
    n = len(texture.layers)
    h, w = texture.tile_shape
    return f"""# spectex texture: GLSL

Written by `spectex export`. {n} layers over {len(tiles)} tile(s) of {w} x {h} texels
({', '.join(f'{layer.size:g} m' for layer in texture.layers)}). Every shader here is the
text spectex's own OpenGL renderer compiles, with the first lines for its dialect.

| file | what |
|---|---|
| `spectex_layers.es300.glsl`, `spectex_layers.330.glsl` | the layer library alone (sampling, blending, haze, sky), for your own `main()` |
| `ground.es300.vert`, `ground.es300.frag` | the ground program, GLSL ES 3.00 (WebGL2) |
| `ground.330.vert`, `ground.330.frag` | the same, desktop GLSL 3.30 |
| `spectex_texture.json` | the layer table and the atmosphere |
| `spectex_uniforms.js` | `spectexTextureUniforms(table)`, `spectexFrameUniforms(table, x, y, z, yaw, pitch, fov, width, height)` |
| {', '.join(f'`{t}`' for t in tiles)} | the tile(s), RGBA, lossless; alpha is data (the blend weight) |
| `mips/` | every mip level spectex samples ({levels} per tile), for exact texels |

The ground program draws one full-screen triangle (no vertex buffer: it uses
`gl_VertexID`); each pixel casts its ray from the camera to the ground plane
`z = 0` (spectex's world: metres, `x` east, `y` north, `z` up), samples each
layer with `textureLod` at the footprint's level of detail, blends the layers,
and adds spectex's sky and haze. Uniforms:

* from the texture, once: `u_tile` (sampler array, one unit per tile),
  `u_tex_size`, `u_mat`, `u_opacity`, `u_lod_off`, `u_mean`;
* per frame: `u_size` (framebuffer width, height), `u_height`, `u_fwd`,
  `u_right`, `u_up`, `u_tan`, `u_ddx`, `u_ddy`, `u_horizon`, `u_zenith`, `u_haze`,
  `u_far`, `u_anchor`;
* filtering: `u_max_aniso` (1 = trilinear only, up to 16).

`spectex_uniforms.js` computes all of them as spectex does, in float64: the
layer anchors `u_anchor[k] = M_k (camera - offset_k) mod 2` are what keep the
shader precise thousands of kilometres from the origin. From another language,
follow `docs/sampling.md` (sections 6 and 7) or that file; it is 60 lines.

## Textures

Tile `i` goes to texture unit `i`, `u_tile[i] = i`. To sample exactly the
texels spectex samples: RGBA8 (16-bit PNGs: a float format), wrap `REPEAT` on
both axes, minification `LINEAR_MIPMAP_LINEAR`, magnification `LINEAR`, the
levels from `mips/` uploaded one by one (not `glGenerateMipmap`, whose box
filter is not specified), rows in file order (row 0 of the PNG is `t = 0`: no
vertical flip), no premultiplied alpha, no sRGB decoding (the tile is data in
[0, 1]; do not use an `SRGB8_ALPHA8` format). The anisotropic path is the
shader's own (EXT_texture_filter_anisotropic's formula with `textureLod` taps),
so do not also enable the driver's anisotropic filtering.

## three.js

```js
import * as THREE from 'three';
import {{ spectexTextureUniforms, spectexFrameUniforms }} from './spectex_uniforms.js';

const table = await (await fetch('spectex_texture.json')).json();
const [vert, frag] = await Promise.all(['ground.es300.vert', 'ground.es300.frag']
  .map(async (f) => (await fetch(f)).text()));
// three.js writes "#version 300 es" itself for glslVersion GLSL3: drop ours.
const strip = (s) => s.replace(/^#version[^\\n]*\\n/, '');

// Each tile with spectex's own mip levels: no flip, no premultiply, no colour conversion.
const loader = new THREE.ImageBitmapLoader().setOptions(
  {{ imageOrientation: 'none', premultiplyAlpha: 'none', colorSpaceConversion: 'none' }});
async function tile(name, levels) {{
  const images = await Promise.all([...Array(levels).keys()]
    .map((d) => loader.loadAsync(`mips/${{name}}.level${{d}}.png`)));
  const t = new THREE.Texture(images[0]);
  t.mipmaps = images;                      // spectex's levels, not generated ones
  t.generateMipmaps = false;
  t.flipY = false;                         // row 0 of the PNG is t = 0
  t.premultiplyAlpha = false;              // alpha is data: the layer's blend weight
  t.colorSpace = THREE.NoColorSpace;       // the tile is data, not sRGB colour
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.minFilter = THREE.LinearMipmapLinearFilter;
  t.magFilter = THREE.LinearFilter;
  t.needsUpdate = true;
  return t;
}}
const tiles = await Promise.all({json.dumps([t.rsplit('.', 1)[0] for t in tiles])}.map((n) => tile(n, {levels})));

const uniforms = {{ u_tile: {{ value: tiles }}, u_max_aniso: {{ value: 8 }} }};
for (const [k, v] of Object.entries(spectexTextureUniforms(table))) uniforms[k] = {{ value: v }};
const material = new THREE.RawShaderMaterial({{
  glslVersion: THREE.GLSL3, vertexShader: strip(vert), fragmentShader: strip(frag),
  uniforms, depthTest: false, depthWrite: false,
}});
const geometry = new THREE.BufferGeometry();  // three vertices; the shader makes the triangle
geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(9), 3));
const ground = new THREE.Mesh(geometry, material);
ground.frustumCulled = false;
scene.add(ground);

// Every frame, from a spectex camera (x, y, z in metres, yaw, pitch, fov in degrees):
function update(x, y, z, yaw, pitch, fov) {{
  const size = renderer.getDrawingBufferSize(new THREE.Vector2());
  const f = spectexFrameUniforms(table, x, y, z, yaw, pitch, fov, size.x, size.y);
  for (const [k, v] of Object.entries(f)) (uniforms[k] ??= {{ value: null }}).value = v;
}}
update(0, 0, 2, 0, -10, 60);  // before the first render, so that every uniform has a value
```

From a three.js camera in a Y-up scene (spectex `x, y, z` = three `X, -Z, Y`;
no roll): `d = camera.getWorldDirection(new THREE.Vector3())`, `yaw =
atan2(d.x, -d.z)`, `pitch = asin(d.y)` (in degrees), `fov = camera.fov`.

## Your own shader: the layer library

`spectex_layers.<target>.glsl` is the prelude, the constants and the layer
library: no uniforms, no `main()`; append your declarations and `main()` to it.
For a ground mesh: pass the world position to the fragment shader as spectex
ground coordinates relative to an anchor point `a` near the camera (`p =
(X, -Z) - a` in a Y-up scene), set `anchor[k] = M_k (a - offset_k) mod 2` per
layer from the host in double precision (as `spectexFrameUniforms` does with
the camera), and per layer:

```glsl
vec2 jx = dFdx(p), jy = dFdy(p);              // the pixel's footprint on the ground
vec2 st = spectex_layer_coords(anchor[k], mat[k], p);
vec2 dx = spectex_layer_deriv(mat[k], jx), dy = spectex_layer_deriv(mat[k], jy);
vec4 x = spectex_sample_grad(tile0, st, dx, dy, tex_size, max_aniso);
float lam = spectex_fade_lod(dx, dy, tex_size);   // used by SPX_BLEND_FINE and SPX_BLEND_COVER only
c = spectex_blend(SPX_BLEND_VARIANCE, c, x, opacity[k], mean[k], lam);   // the layer's blend; SPX_BLEND_FIRST for the first
```

`spectex_texture.json` has `matrix` (`M_k` as m00, m01, m10, m11), `offset`,
`opacity`, `mean` and `blend` per layer. `dFdx`/`dFdy` are per 2 x 2 pixel
quad, not spectex's exact per-pixel derivatives: the level of detail can
differ slightly from spectex's at steep angles.
""" + (_stochastic_readme(texture) if has_stochastic(texture) else "")  # noqa: E501 (table rows and code the reader copies: not wrapped)


def _stochastic_readme(texture) -> str:
    from spectex.shading.constants import LUT_SIZE

    from ._stochastic import LUT_FILE, gauss_name, table_info

    info = table_info(texture)
    gauss = ", ".join(f"`{gauss_name(texture, i)}`" for i in range(len(texture.tiles)))
    shapes = ", ".join(f"{w} x {h}" for h, w in info["level_shapes"])
    n = len(texture.tiles)
    stochastic = [k for k, layer in enumerate(texture.layers) if layer.tiling == "stochastic"]
    return f"""
## Stochastic layers

Layer(s) {', '.join(str(k) for k in stochastic)} use spectex's stochastic tiling
(histogram-preserving tiling and blending): they never repeat. They sample no
tile but two textures made from it, shipped losslessly as raw files of
little-endian IEEE half floats, rows top first (row 0 is `t = 0`, no flip):

| file | texture |
|---|---|
| {gauss} | per tile, its Gaussianised levels: RGBA16F, every mip level one after the other ({shapes}); wrap `REPEAT`, `LINEAR_MIPMAP_LINEAR`/`LINEAR` like the tiles |
| `{LUT_FILE}` | the look-up tables: R16F, {LUT_SIZE} x {4 * info['lut_rows']}, one level; `NEAREST`/`NEAREST`, `CLAMP_TO_EDGE` |

Units: tile `i` on unit `i`, its Gaussianised levels on unit `{n} + i`
(`u_gauss[i]`), the table on unit `{2 * n}` (`u_lut`). More uniforms, all from
`spectex_texture.json` (`spectexTextureUniforms` sets them): `u_lut_rows`,
`u_lut_q`, and per layer `u_grid`, `u_key` (uint), `u_snap` (vec2), `u_lut_row`, `u_basis`
(mat3, column-major), `u_origin`; per frame (`spectexFrameUniforms`) the
anchor's position in each stochastic layer's triangle grid, computed in
float64 on the host from the same `(s, t) = M_k (camera - offset_k)` *before*
the reduction mod 2: `k = G_k (s, t)` (`G_k` is the layer's `grid`),
`u_ganchor[k] = k - floor(k)` and `u_gbase[k] = floor(k) mod 2^32` (uvec2).
The grid vertex is hashed by its index, so it is passed whole: this is what
keeps a stochastic layer exact thousands of kilometres from the origin.

three.js (after the code above):

```js
async function halves(name) {{ return new Uint16Array(await (await fetch(name)).arrayBuffer()); }}
const shapes = table.stochastic.level_shapes;  // [height, width] per level
function gaussTexture(data) {{
  let at = 0;
  const mipmaps = shapes.map(([h, w]) => {{ const m = {{ data: data.subarray(at, at + 4 * w * h), width: w, height: h }}; at += 4 * w * h; return m; }});
  const t = new THREE.DataTexture(mipmaps[0].data, shapes[0][1], shapes[0][0], THREE.RGBAFormat, THREE.HalfFloatType);
  t.mipmaps = mipmaps;
  t.generateMipmaps = false;
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.minFilter = THREE.LinearMipmapLinearFilter;
  t.magFilter = THREE.LinearFilter;
  t.needsUpdate = true;
  return t;
}}
uniforms.u_gauss = {{ value: await Promise.all({json.dumps([gauss_name(texture, i) for i in range(n)])}.map(async (f) => gaussTexture(await halves(f)))) }};
const lut = new THREE.DataTexture(await halves('{LUT_FILE}'), {LUT_SIZE}, {4 * info['lut_rows']}, THREE.RedFormat, THREE.HalfFloatType);
lut.minFilter = lut.magFilter = THREE.NearestFilter;
lut.needsUpdate = true;
uniforms.u_lut = {{ value: lut }};
```

In your own shader, a stochastic layer is `spectex_sample_stochastic_grad` (see
the library's comments and `ground.*.frag`'s `shade_layer_stochastic`) instead
of `spectex_sample_grad`, with the grid position `g = u_ganchor[k] + G_k M_k p`.
"""  # noqa: E501 (table rows and code the reader copies: not wrapped)


def write_glsl(texture, folder: Path) -> list[Path]:
    """Write ``folder/glsl/``; return the files written."""
    from spectex.io import write_image

    from ._stochastic import write_tables
    from ._tiles import tile_names
    from .web import layer_table, uniforms_js

    out = Path(folder) / "glsl"
    (out / "mips").mkdir(parents=True)
    files = []
    for target in GLSL_TARGETS:
        path = out / f"spectex_layers.{target}.glsl"
        path.write_text(prelude(target) + layer_library(anisotropic=True), encoding="utf-8")
        files.append(path)
        for suffix, text in (("vert", vertex_source(target)), ("frag", ground_fragment(texture, target))):
            path = out / f"ground.{target}.{suffix}"
            path.write_text(text, encoding="utf-8")
            files.append(path)
    path = out / "spectex_texture.json"
    path.write_text(json.dumps(layer_table(texture), indent=1) + "\n", encoding="utf-8")
    files.append(path)
    path = out / "spectex_uniforms.js"
    path.write_text(uniforms_js() + "\nexport { spectexTextureUniforms, spectexFrameUniforms };\n", encoding="utf-8")
    files.append(path)
    names = tile_names(texture)
    depth = 8 if texture.bits == 8 else 16
    for name, tile, levels in zip(names, texture.tiles, mip_levels(texture)):
        files.append(write_image(out / name, tile, bit_depth=depth))
        stem = name.rsplit(".", 1)[0]
        for d, level in enumerate(levels):
            files.append(write_image(out / "mips" / f"{stem}.level{d}.png", level, bit_depth=depth))
    files += write_tables(texture, out)
    path = out / "README.md"
    path.write_text(_readme(texture, names, len(mip_levels(texture)[0])), encoding="utf-8")
    files.append(path)
    return files
