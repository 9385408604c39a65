// spectex: the uniforms of the renderer's ground shader (ground.frag), computed
// as spectex.render does (docs/sampling.md, sections 6 and 7). Plain functions,
// no libraries. `texture` is the exported layer table (spectex_texture.json or
// the viewer's own copy): {tile_shape, layers: [{matrix, offset, opacity,
// lod_offset, mean, tiling, and for stochastic layers grid, key, snap, lut_row, basis,
// origin}], stochastic: null or {lut_rows, lut_q}, atmosphere: {horizon, zenith,
// haze_distance}}.

// Uniforms that depend only on the texture.
function spectexTextureUniforms(texture) {
  const L = texture.layers;
  const out = {
    u_tex_size: [texture.tile_shape[1], texture.tile_shape[0]],
    u_mat: [].concat(...L.map((l) => l.matrix)),         // per layer (m00, m01, m10, m11): world -> tile
    u_opacity: L.map((l) => l.opacity),
    u_lod_off: L.map((l) => l.lod_offset),               // log2(tile width / layer size)
    u_mean: [].concat(...L.map((l) => l.mean)),          // the tile's mean colour (variance blend)
  };
  if (texture.stochastic) {  // stochastic layers (docs/sampling.md, section 6b); zeros for periodic ones
    const pick = (l, name, zero) => (l.tiling === "stochastic" ? l[name] : zero);
    out.u_lut_rows = texture.stochastic.lut_rows;      // rows of the table texture per channel
    out.u_lut_q = texture.stochastic.lut_q;            // the last mip level
    out.u_grid = [].concat(...L.map((l) => pick(l, "grid", [0, 0, 0, 0])));  // tile -> skewed grid
    out.u_key = L.map((l) => pick(l, "key", 0));       // the hash key of the layer's seed (uint32)
    out.u_snap = [].concat(...L.map((l) => pick(l, "snap", [1, 1])));  // snap counts along s, t (whole numbers)
    out.u_lut_row = L.map((l) => pick(l, "lut_row", 0));
    // mat3 is column-major: basis is row-major, so its transpose, row after row
    out.u_basis = [].concat(...L.map((l) => {
      const b = pick(l, "basis", [0, 0, 0, 0, 0, 0, 0, 0, 0]);
      return [b[0], b[3], b[6], b[1], b[4], b[7], b[2], b[5], b[8]];
    }));
    out.u_origin = [].concat(...L.map((l) => pick(l, "origin", [0, 0, 0])));
  }
  return out;
}

// Uniforms of one frame: a camera at (x, y, z) metres (z up, z > 0), compass
// heading yaw (degrees, 0 looks along +y, 90 along +x), pitch (degrees above
// the horizon), vertical field of view fov (degrees), a width x height picture.
// Everything is float64 here; the layer anchors M_k (camera - offset_k) mod 2
// keep the shader's numbers small anywhere on the plane. For a stochastic layer
// also the anchor in its triangle grid, k = G_k M_k (camera - offset_k) (not
// reduced): its fraction k - floor(k) (u_ganchor) and the grid vertex floor(k)
// mod 2^32 (u_gbase), whose hash picks the patches (spectex.shading.tables.anchor_coords).
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
    anchor.push(mod(s, 2), mod(t, 2));
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
  const haze = given > 0 ? given : 1e30;  // 0: no haze (spectex's Atmosphere(haze_distance=0), HAZE_OFF)
  const out = {
    u_size: [width, height],
    u_height: z,
    u_fwd: fwd,
    u_right: right,
    u_up: up,
    u_tan: [tanX, tanY],
    u_ddx: right.map((c) => c * 2 * tanX / width),      // d(ray)/d(pixel x)
    u_ddy: up.map((c) => -c * 2 * tanY / height),       // d(ray)/d(pixel y), row 0 at the top
    u_horizon: texture.atmosphere.horizon,
    u_zenith: texture.atmosphere.zenith,
    u_haze: haze,
    u_far: 50 * haze,
    u_anchor: anchor,
  };
  if (texture.stochastic) {
    out.u_ganchor = ganchor;
    out.u_gbase = gbase;
  }
  return out;
}
