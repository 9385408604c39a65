// spectex: the uniforms of the renderer's ground shader (ground.frag), computed
// as spectex.render does (docs/sampling.md, sections 6 and 7). Plain functions,
// no libraries. `texture` is the exported layer table (spectex_texture.json or
// the viewer's own copy): {tile_shape, layers: [{matrix, offset, opacity,
// lod_offset, mean, tiling, and for stochastic layers grid, key, snap, lut_row, basis,
// origin}], stochastic: null or {lut_rows, lut_q}, atmosphere: {horizon, zenith,
// haze_distance}}.

// Uniforms that depend only on the texture. (The entries: spectex/shading/interface.py.)
function spectexTextureUniforms(texture) {
  const L = texture.layers;
  const pick = (l, name, zero) => (l.tiling === "stochastic" ? l[name] : zero);  // zeros for periodic layers
  const out = {
/*@TEXTURE@*/
  };
  if (texture.stochastic) {  // stochastic layers (docs/sampling.md, section 6b)
/*@TEXTURE_STOCHASTIC@*/
  }
  return out;
}

// The texture units: tile i on unit i, its Gaussianised levels on nTiles + i, the table on 2 nTiles.
function spectexUnitUniforms(nTiles, stochastic) {
  const out = {
/*@UNIT@*/
  };
  if (stochastic) {
/*@UNIT_STOCHASTIC@*/
  }
  return out;
}

// The filter settings: spectex's anisotropic filter, at most maxAniso samples (1: off).
function spectexSamplerUniforms(maxAniso) {
  return {
/*@SAMPLER@*/
  };
}

// Uniforms of one frame: a camera at (x, y, z) metres (z up, z > 0), compass
// heading yaw (degrees, 0 looks along +y, 90 along +x), pitch (degrees above
// the horizon), vertical field of view fov (degrees), a width x height picture.
// Everything is float64 here; the layer anchors M_k (camera - offset_k) mod 2
// keep the shader's numbers small anywhere on the plane. For a stochastic layer
// also the anchor in its triangle grid, k = G_k M_k (camera - offset_k) (not
// reduced): its fraction k - floor(k) and the grid vertex floor(k)
// mod 2^32, whose hash picks the patches (spectex.shading.tables.anchor_coords).
function spectexFrameUniforms(texture, x, y, z, yaw, pitch, fov, width, height, hazeDistance) {
  const DEG = Math.PI / 180;
  const cy = Math.cos(yaw * DEG), sy = Math.sin(yaw * DEG);
  const cp = Math.cos(pitch * DEG), sp = Math.sin(pitch * DEG);
  const fwd = [cp * sy, cp * cy, sp];
  const right = [cy, -sy, 0];
  const up = [right[1] * fwd[2] - right[2] * fwd[1], right[2] * fwd[0] - right[0] * fwd[2],
              right[0] * fwd[1] - right[1] * fwd[0]];
  const tanY = Math.tan(fov * DEG / 2), tanX = tanY * width / height;
  const mod = function (v, n) {  // as Python's v % n: in [0, n)
    const r = v % n;
    return r < 0 ? r + n : r;
  };
  const anchor = [], ganchor = [], gbase = [];
  for (const layer of texture.layers) {
    const m = layer.matrix, dx = x - layer.offset[0], dy = y - layer.offset[1];
    const s = m[0] * dx + m[1] * dy, t = m[2] * dx + m[3] * dy;
    anchor.push(mod(s, /*@ANCHOR_PERIOD@*/), mod(t, /*@ANCHOR_PERIOD@*/));
    if (layer.tiling === "stochastic") {
      const g = layer.grid;
      const kx = g[0] * s + g[1] * t, ky = g[2] * s + g[3] * t;
      const bx = Math.floor(kx), by = Math.floor(ky);
      ganchor.push(kx - bx, ky - by);
      gbase.push(mod(bx, 4294967296), mod(by, 4294967296));
    } else {
      ganchor.push(0, 0);
      gbase.push(0, 0);
    }
  }
  const given = hazeDistance === undefined ? texture.atmosphere.haze_distance : hazeDistance;
  const haze = given > 0 ? given : /*@HAZE_OFF@*/;  // 0: no haze (spectex's Atmosphere(haze_distance=0), HAZE_OFF)
  const out = {
/*@FRAME@*/
  };
  if (texture.stochastic) {
/*@FRAME_STOCHASTIC@*/
  }
  return out;
}
