// spectex: the uniforms of the renderer's ground shader (ground.frag), computed
// as spectex.render does (docs/sampling.md, sections 6 and 7). Plain functions,
// no libraries. `texture` is the exported layer table (spectex_texture.json or
// the viewer's own copy): {tile_shape, layers: [{matrix, offset, opacity,
// lod_offset, mean}], atmosphere: {horizon, zenith, haze_distance}}.

// Uniforms that depend only on the texture.
function spectexTextureUniforms(texture) {
  const L = texture.layers;
  return {
    u_tex_size: [texture.tile_shape[1], texture.tile_shape[0]],
    u_mat: [].concat(...L.map((l) => l.matrix)),         // per layer (m00, m01, m10, m11): world -> tile
    u_opacity: L.map((l) => l.opacity),
    u_lod_off: L.map((l) => l.lod_offset),               // log2(tile width / layer size)
    u_mean: [].concat(...L.map((l) => l.mean)),          // the tile's mean colour (variance blend)
  };
}

// Uniforms of one frame: a camera at (x, y, z) metres (z up, z > 0), compass
// heading yaw (degrees, 0 looks along +y, 90 along +x), pitch (degrees above
// the horizon), vertical field of view fov (degrees), a width x height picture.
// Everything is float64 here; the layer anchors M_k (camera - offset_k) mod 2
// keep the shader's numbers small anywhere on the plane.
function spectexFrameUniforms(texture, x, y, z, yaw, pitch, fov, width, height, hazeDistance) {
  const DEG = Math.PI / 180;
  const cy = Math.cos(yaw * DEG), sy = Math.sin(yaw * DEG);
  const cp = Math.cos(pitch * DEG), sp = Math.sin(pitch * DEG);
  const fwd = [cp * sy, cp * cy, sp];
  const right = [cy, -sy, 0];
  const up = [right[1] * fwd[2] - right[2] * fwd[1], right[2] * fwd[0] - right[0] * fwd[2],
              right[0] * fwd[1] - right[1] * fwd[0]];
  const tanY = Math.tan(fov * DEG / 2), tanX = tanY * width / height;
  const anchor = [];
  for (const layer of texture.layers) {
    const m = layer.matrix, dx = x - layer.offset[0], dy = y - layer.offset[1];
    for (const v of [m[0] * dx + m[1] * dy, m[2] * dx + m[3] * dy]) {
      let r = v % 2;  // as Python's v % 2: in [0, 2)
      if (r < 0) r += 2;
      anchor.push(r);
    }
  }
  const haze = hazeDistance === undefined ? texture.atmosphere.haze_distance : hazeDistance;
  return {
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
}
